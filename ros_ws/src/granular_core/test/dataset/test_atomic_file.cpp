// Files written whole or not at all, and output paths refused before the work.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/dataset/atomic_file.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

using AtomicFileTest = TemporaryFolderTest;

std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

// Entries of `folder`, hidden ones included.
std::size_t entries(const fs::path& folder) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
}

TEST_F(AtomicFileTest, AFileIsReplacedWholeAndNoTemporaryIsLeft) {
  const fs::path file = root_ / "results.json";
  writeFileAtomically(file, "first\n", "JSON");
  writeFileAtomically(file, "second, longer\n", "JSON");
  EXPECT_EQ(read(file), "second, longer\n");
  EXPECT_EQ(entries(root_), 1u);
}

TEST_F(AtomicFileTest, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path file = write("model.yml", "old\n");
  const std::string error = errorOf([&] {
    writeThroughTemporary(file, "classifier", [](const fs::path& partial) {
      std::ofstream(partial) << "half";
      return false;
    });
  });
  EXPECT_EQ(error.rfind(file.string() + ": cannot write classifier (through ", 0), 0u) << error;
  EXPECT_EQ(read(file), "old\n");
  EXPECT_EQ(entries(root_), 1u);
}

TEST_F(AtomicFileTest, TheTemporaryIsAHiddenSiblingNamedByKindAndProcess) {
  EXPECT_EQ(temporarySibling(root_ / "out.json", "partial"),
            root_ / (".out.json.partial-" + std::to_string(::getpid())));
}

TEST_F(AtomicFileTest, AWriteIntoAMissingFolderNamesTheFileWhatAndWhy) {
  const fs::path file = root_ / "missing" / "cloud.pcd";
  const std::string error = errorOf([&] { writeFile(file, "x", "PCD"); });
  EXPECT_EQ(error.rfind(file.string() + ": cannot write PCD: ", 0), 0u) << error;
  EXPECT_FALSE(fs::exists(file));
}

TEST_F(AtomicFileTest, CheckCanWriteRefusesWhatCouldNotBeWrittenAndSaysWhy) {
  EXPECT_EQ(errorOf([&] { checkCanWrite(root_ / "out.json", "JSON"); }), "");
  fs::create_directories(root_ / "folder");
  EXPECT_EQ(errorOf([&] { checkCanWrite(root_ / "folder", "JSON"); }),
            (root_ / "folder").string() + ": cannot write JSON: it is a folder");
  const fs::path missing = root_ / "a" / "b" / "out.json";
  EXPECT_EQ(errorOf([&] { checkCanWrite(missing, "JSON"); }),
            missing.string() + ": cannot write JSON: its folder " + (root_ / "a" / "b").string() +
                " does not exist");
  const fs::path regular = write("regular", "");
  EXPECT_EQ(errorOf([&] { checkCanWrite(regular / "out.json", "JSON"); }),
            (regular / "out.json").string() + ": cannot write JSON: " + regular.string() +
                " is not a folder");
}

}  // namespace
}  // namespace granular
