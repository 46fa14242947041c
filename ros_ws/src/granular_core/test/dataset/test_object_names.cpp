// Labels round-trip exactly through object and model file names (the cases in
// test/data/label_names.tsv are granular_tools/labels.py's too).
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/dataset/object_names.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

std::vector<std::pair<std::string, std::string>> labelCases() {
  std::ifstream stream(fs::path(GRANULAR_CORE_TEST_DATA) / "label_names.tsv");
  std::vector<std::pair<std::string, std::string>> cases;
  std::string line;
  std::getline(stream, line);  // header
  while (std::getline(stream, line)) {
    const std::size_t tab = line.find('\t');
    cases.emplace_back(line.substr(0, tab), line.substr(tab + 1));
  }
  return cases;
}

TEST(ObjectNamesTest, EveryLabelRoundTripsThroughItsFileNames) {
  const auto cases = labelCases();
  ASSERT_GE(cases.size(), 10u);
  for (const auto& [label, encoded] : cases) {
    EXPECT_EQ(encodeLabel(label), encoded);
    EXPECT_EQ(decodeLabel(encoded), label);
    const std::string object = objectFileName(label, "1586102742000765440", 3);
    EXPECT_EQ(object, encoded + "-1586102742000765440-3.pcd");
    EXPECT_EQ(objectClass(object), label);
    EXPECT_EQ(modelClass(modelFileName(label)), label);
    EXPECT_NE(object[0], '.') << label << " would hide its file";
    EXPECT_EQ(object.find('/'), std::string::npos);
  }
}

TEST(ObjectNamesTest, PlainLabelsKeepTheReportsNames) {
  EXPECT_EQ(objectFileName("Hatchback", "1589078382118914", 2),
            "Hatchback-1589078382118914-2.pcd");
  EXPECT_EQ(modelFileName("SchoolBus"), "SchoolBus.pcd");
}

TEST(ObjectNamesTest, LabelsThatCannotNameAFileAreRefused) {
  EXPECT_THROW(objectFileName("", "1", 1), std::invalid_argument);
  EXPECT_THROW(objectFileName(std::string(201, 'A'), "1", 1), std::invalid_argument);
  EXPECT_NO_THROW(objectFileName(std::string(200, 'A'), "1", 1));
  EXPECT_THROW(modelFileName(std::string(67, '/')), std::invalid_argument);  // 201 encoded
}

TEST(ObjectNamesTest, NamesNoEncodingGivesHaveNoClass) {
  EXPECT_EQ(objectClass("-1-1.pcd"), "");
  EXPECT_EQ(objectClass("stray.pcd"), "");
  EXPECT_EQ(objectClass("Bad%2-1-1.pcd"), "");    // a cut escape
  EXPECT_EQ(objectClass("Bad%2d-1-1.pcd"), "");   // lower-case hex
  EXPECT_EQ(objectClass("Bad%41-1-1.pcd"), "");   // 'A' escaped
  EXPECT_EQ(objectClass("Bad label-1-1.pcd"), "");
  EXPECT_EQ(decodeLabel(""), std::nullopt);
}

}  // namespace
}  // namespace granular
