// A temporary folder per test, shared by the tests that read and write files.
#pragma once

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace granular {
namespace testing_support {

namespace fs = std::filesystem;

// A fresh folder under the system temporary folder, removed with the fixture.
class TemporaryFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    root_ = fs::temp_directory_path() /
            ("granular_core_test_" + std::to_string(entropy()) + std::to_string(entropy()));
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path write(const fs::path& relative, const std::string& content) const {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << content;
    return path;
  }

  static std::string read(const fs::path& path) {
    std::ifstream stream(path);
    std::stringstream content;
    content << stream.rdbuf();
    return content.str();
  }

  fs::path root_;
};

}  // namespace testing_support
}  // namespace granular
