#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_ros/command_line.h"

namespace granular_ros {
namespace {

// Parses `arguments` (after the tool's name) with a table of --help, two required options
// and an optional one, as the tools declare theirs.
struct Parsed {
  bool help = false;
  std::string objects;
  std::string out;
  std::string preset = "report";
};

Parsed parse(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), "tool");
  std::vector<char*> argv;
  for (std::string& argument : arguments) {
    argv.push_back(argument.data());
  }
  Parsed parsed;
  OptionTable()
      .help(parsed.help)
      .required("--objects", parsed.objects, "FOLDER", "objects to classify")
      .required("--out", parsed.out, "FILE.json", "results file to write")
      .value("--preset", parsed.preset, "NAME", "parameter set")
      .parse(static_cast<int>(argv.size()), argv.data());
  return parsed;
}

std::string errorOf(const std::vector<std::string>& arguments) {
  try {
    parse(arguments);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(OptionTableTest, RequiredOptionsAreReadLikeAnyOther) {
  const Parsed parsed = parse({"--objects", "objects", "--out=results.json"});
  EXPECT_EQ(parsed.objects, "objects");
  EXPECT_EQ(parsed.out, "results.json");
  EXPECT_EQ(parsed.preset, "report");
  EXPECT_FALSE(parsed.help);
}

TEST(OptionTableTest, AMissingRequiredOptionNamesThemAll) {
  EXPECT_EQ(errorOf({"--objects", "objects"}), "--objects and --out are required");
  EXPECT_EQ(errorOf({}), "--objects and --out are required");
  EXPECT_EQ(errorOf({"--out", ""}), "--objects and --out are required");  // empty is missing
}

TEST(OptionTableTest, HelpNeedsNoRequiredOption) {
  EXPECT_TRUE(parse({"--help"}).help);
  EXPECT_TRUE(parse({"-h", "--preset", "tuned"}).help);
}

TEST(OptionTableTest, HelpWinsOverEveryOtherMistake) {
  EXPECT_TRUE(parse({"--outt", "x", "--help"}).help);
  EXPECT_TRUE(parse({"--help", "--bogus"}).help);
  EXPECT_TRUE(parse({"--objects", "-h", "--preset"}).help);
}

TEST(OptionTableTest, OneRequiredOptionIsNamedAlone) {
  std::string frames;
  std::vector<std::string> arguments = {"tool"};
  std::vector<char*> argv = {arguments[0].data()};
  try {
    OptionTable().required("--frames", frames, "FOLDER", "frames").parse(1, argv.data());
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "--frames is required");
  }
}

TEST(OptionTableTest, UnknownOptionsAreStillErrors) {
  EXPECT_NE(errorOf({"--objects", "o", "--out", "r", "--outt", "x"}), "");
}

TEST(OptionTableTest, HelpListsEveryOptionOnceInTheOrderDeclared) {
  bool help = false;
  bool transforms = false;
  std::string out;
  int threads = 0;
  OptionTable table;
  table.required("--out", out, "FILE.json", "results file to write (replaced)")
      .flag("--transforms", transforms,
            "also write each pair's final transform (16 numbers, row-major; the file grows "
            "about threefold)\nnot read by svm_fitness")
      .threads("--threads", threads, "threads (default: every core)")
      .value("--a-very-long-option-name", out, "FILE.json[,FILE.json...]", "results files")
      .help(help);
  EXPECT_EQ(table.help(),
            "  --out FILE.json        results file to write (replaced)\n"
            "  --transforms           also write each pair's final transform (16 numbers, "
            "row-major;\n"
            "                         the file grows about threefold)\n"
            "                         not read by svm_fitness\n"
            "  --threads N            threads (default: every core)\n"
            "  --a-very-long-option-name FILE.json[,FILE.json...]\n"
            "                         results files\n"
            "  -h, --help             print this help and exit\n");
}

}  // namespace
}  // namespace granular_ros
