// Two synthetic classes of objects, for the supervised classifiers' tests.
#pragma once

#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/point_types.h"

namespace granular {
namespace testing_support {

// Two well separated synthetic classes: boxes 4.5 m long, 1.5 m high and boxes 2 m long, 2.5 m
// high, seen from a random side, with a little noise.
class TwoClassesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(3);
    std::normal_distribution<float> noise(0.0f, 0.02f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 60; ++i) {
      const bool car = i % 2 == 0;
      const float length = car ? 4.5f : 2.0f, height = car ? 1.5f : 2.5f;
      Cloud cloud;
      for (int p = 0; p < 300; ++p) {
        // The left side and the front.
        const bool side = unit(random) < 0.7f;
        const float x = side ? (unit(random) - 0.5f) * length : length / 2;
        const float y = side ? 0.9f : (unit(random) - 0.5f) * 1.8f;
        cloud.push_back(PointXYZIT(x + noise(random), y + noise(random),
                                   unit(random) * height, car ? 200 : 50, 0.0));
      }
      (i < 40 ? train_ : test_).push_back(cloud);
      (i < 40 ? train_labels_ : test_labels_).push_back(car ? "Car" : "Van");
    }
  }

  std::vector<Cloud> train_, test_;
  std::vector<std::string> train_labels_, test_labels_;
};

}  // namespace testing_support
}  // namespace granular
