// A YAML file of one test's own, and the message of loading it: shared by the config tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace granular_ros {

class TemporaryYamlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    file_ = std::filesystem::temp_directory_path() /
            ("granular_ros_config_" + std::to_string(entropy()) + std::to_string(entropy()) +
             ".yaml");
  }
  void TearDown() override { std::filesystem::remove(file_); }

  void write(const std::string& content) const { std::ofstream(file_) << content; }

  // The message of load(file_) with `content` in the file, which must fail naming the file.
  template <typename Load>
  std::string errorOf(const std::string& content, Load load) const {
    write(content);
    try {
      load(file_);
    } catch (const std::runtime_error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(file_.string()), std::string::npos) << message;
      return message;
    }
    ADD_FAILURE() << "accepted: " << content;
    return "";
  }

  std::filesystem::path file_;
};

}  // namespace granular_ros
