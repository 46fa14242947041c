// OutputFolder and the atomic writers: what a user's folder looks like after every outcome of a
// run (done, failed, refused, interrupted, killed), and that two runs never share a folder.
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/dataset/output_folder.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

class OutputFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("granular_output_folder_" + std::to_string(::getpid()) + "_" +
             std::to_string(std::random_device()()));
    fs::create_directories(root_);
    target_ = root_ / "out";
  }
  void TearDown() override { fs::remove_all(root_); }

  static std::string read(const fs::path& path) {
    std::ifstream stream(path);
    std::stringstream text;
    text << stream.rdbuf();
    return text.str();
  }

  static void write(const fs::path& path, const std::string& content) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << content;
  }

  std::set<std::string> entries(const fs::path& folder) const {
    std::set<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
      names.insert(entry.path().filename().string());
    }
    return names;
  }

  std::string refusal(const OutputPolicy& policy) const {
    try {
      OutputFolder output(target_, "test_tool", policy);
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "accepted";
  }

  // A pid that belonged to a process that has ended.
  static pid_t deadPid() {
    const pid_t child = ::fork();
    if (child == 0) {
      ::_exit(0);
    }
    ::waitpid(child, nullptr, 0);
    return child;
  }

  fs::path root_;
  fs::path target_;
};

TEST_F(OutputFolderTest, ACommittedFolderCarriesItsManifestAndNothingIsLeftBeside) {
  {
    OutputFolder output(target_, "test_tool");
    EXPECT_EQ(output.staging().parent_path(), root_);
    EXPECT_EQ(output.staging().filename().string().rfind(".out.partial-", 0), 0u);
    write(output.staging() / "result.txt", "done");
    EXPECT_FALSE(fs::exists(target_)) << "visible before the commit";
    output.commit();
  }
  EXPECT_EQ(read(target_ / "result.txt"), "done");
  const std::string manifest = read(target_ / kManifestName);
  EXPECT_NE(manifest.find(R"("tool": "test_tool")"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find(std::string(R"("version": ")") + granularVersion() + '"'),
            std::string::npos)
      << manifest;
  EXPECT_EQ(entries(root_), (std::set<std::string>{"out"}));
}

TEST_F(OutputFolderTest, WithoutCommitTheTargetIsLeftAsItWas) {
  {
    OutputFolder output(target_, "test_tool");
    write(output.staging() / "half.txt", "half");
  }
  EXPECT_FALSE(fs::exists(target_));
  EXPECT_TRUE(fs::is_empty(root_));
}

TEST_F(OutputFolderTest, AFolderOfOtherFilesIsNeverReplaced) {
  write(target_ / "thesis.tex", "years of work");
  OutputPolicy policy;
  policy.overwrite = true;
  policy.overwrite_hint = "overwrite:=true";
  const std::string message = refusal(policy);
  EXPECT_NE(message.find(target_.string() + ": output folder holds files that no granular tool "
                                            "wrote (it has no .granular.json); refusing to "
                                            "replace it, even with overwrite:=true"),
            std::string::npos)
      << message;
  EXPECT_EQ(read(target_ / "thesis.tex"), "years of work");
  EXPECT_EQ(entries(target_), (std::set<std::string>{"thesis.tex"}));
  // A file where the folder should be is refused too, and kept.
  fs::remove_all(target_);
  write(target_, "a file");
  EXPECT_NE(refusal(policy).find("output exists and is not a folder"), std::string::npos);
  EXPECT_EQ(read(target_), "a file");
}

TEST_F(OutputFolderTest, AGranularResultIsReplacedOnlyWithOverwrite) {
  {
    OutputFolder first(target_, "first_tool");
    write(first.staging() / "old.txt", "old");
    first.commit();
  }
  OutputPolicy policy;
  EXPECT_NE(refusal(policy).find("holds results of first_tool; pass --overwrite to replace"),
            std::string::npos);
  policy.overwrite = true;
  {
    OutputFolder second(target_, "second_tool", policy);
    write(second.staging() / "new.txt", "new");
    second.commit();
  }
  EXPECT_EQ(entries(target_), (std::set<std::string>{"new.txt", kManifestName}));
  EXPECT_EQ(entries(root_), (std::set<std::string>{"out"}));
}

TEST_F(OutputFolderTest, AFolderThatIsOrHoldsAnInputIsNeverReplaced) {
  {
    OutputFolder first(target_, "first_tool");
    write(first.staging() / "frames" / "pcd" / "1.pcd", "a cloud");
    first.commit();
  }
  OutputPolicy policy;
  policy.overwrite = true;
  // The input itself, a folder inside the output, and a link to the output's folder.
  fs::create_directory_symlink(target_, root_ / "link");
  for (const fs::path& input :
       {target_, target_ / "frames", root_ / "link" / "frames" / "pcd" / "1.pcd"}) {
    try {
      OutputFolder replacing(target_, "second_tool", policy, {root_ / "elsewhere", input});
      ADD_FAILURE() << "accepted an output holding " << input;
    } catch (const std::runtime_error& refused) {
      const std::string message = refused.what();
      EXPECT_NE(message.find("is or holds the input " + input.string()), std::string::npos)
          << message;
    }
    EXPECT_EQ(read(target_ / "frames" / "pcd" / "1.pcd"), "a cloud");
  }
  // Beside the input, or inside it, is fine.
  OutputFolder beside(root_ / "other", "second_tool", policy, {target_ / "frames"});
  OutputFolder inside(target_ / "frames" / "results", "second_tool", policy, {target_ / "frames"});
}

TEST_F(OutputFolderTest, ASecondRunIntoTheSameFolderIsRefusedWhileTheFirstHoldsIt) {
  OutputFolder first(target_, "first_tool");
  const std::string message = refusal(OutputPolicy());
  EXPECT_NE(message.find(target_.string() + ": another granular run is writing this folder "
                                            "(process " +
                         std::to_string(::getpid()) + ", first_tool)"),
            std::string::npos)
      << message;
  // The refused run took nothing away from the first one.
  EXPECT_TRUE(fs::is_directory(first.staging()));
  // Another spelling of the same folder is the same folder.
  target_ = root_ / "." / "out" / "";
  EXPECT_NE(refusal(OutputPolicy()).find("another granular run"), std::string::npos);
  EXPECT_EQ(lockFileOf(root_ / "out"), lockFileOf(root_ / "." / "out"));
  EXPECT_NE(lockFileOf(root_ / "out"), lockFileOf(root_ / "other"));
}

TEST_F(OutputFolderTest, WhatADeadRunLeftIsClearedAndASetAsideResultPutBack) {
  const pid_t dead = deadPid();
  const fs::path staging = root_ / (".out.partial-" + std::to_string(dead));
  const fs::path previous = root_ / (".out.previous-" + std::to_string(dead));
  write(staging / "half.pcd", "half");
  write(previous / "kept.txt", "the user's last good result");
  write(previous / kManifestName, R"({"tool": "extract_objects"})");
  // A live process's staging is not ours to remove.
  const fs::path alive = root_ / ".out.partial-1";
  write(alive / "x", "init's");

  OutputPolicy policy;
  policy.overwrite = true;
  OutputFolder output(target_, "test_tool", policy);
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_FALSE(fs::exists(previous));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_EQ(read(target_ / "kept.txt"), "the user's last good result");
  ASSERT_EQ(output.cleared().size(), 2u);
  EXPECT_EQ(output.cleared()[0], "removed " + staging.string() + ", left by process " +
                                     std::to_string(dead) + ", which is no longer running");
  EXPECT_NE(output.cleared()[1].find("put back " + target_.string()), std::string::npos);
}

TEST_F(OutputFolderTest, PendingOutputsAreRemovedOnRequestAndNotAfterACommit) {
  OutputFolder kept(root_ / "kept", "test_tool");
  write(kept.staging() / "a.txt", "a");
  kept.commit();
  OutputFolder interrupted(target_, "test_tool");
  write(interrupted.staging() / "sub" / "b.txt", "b");
  const std::vector<fs::path> removed = removePendingOutputs();
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0], interrupted.staging());
  EXPECT_FALSE(fs::exists(interrupted.staging()));
  EXPECT_TRUE(fs::exists(root_ / "kept" / "a.txt"));
}

TEST_F(OutputFolderTest, AnAtomicFileLeavesNoTemporaryAndAFailedOneNoFile) {
  const fs::path file = root_ / "result.json";
  writeFileAtomically(file, "{}\n", "JSON");
  EXPECT_EQ(read(file), "{}\n");
  EXPECT_EQ(entries(root_), (std::set<std::string>{"result.json"}));

  const fs::path unwritable = root_ / "no" / "such" / "folder" / "result.json";
  try {
    writeFileAtomically(unwritable, "{}\n", "JSON");
    FAIL() << "a file in a missing folder was written";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()),
              unwritable.string() + ": cannot write JSON: No such file or directory");
  }
  EXPECT_FALSE(fs::exists(root_ / "no"));
}

}  // namespace
}  // namespace granular
