// The feature vectors: mean/std, the paper's point feature histograms.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/supervised/object_features.h"

namespace granular {
namespace {

// Points of a regular grid: x0 + i * step along each axis with more than one value.
std::vector<Eigen::Vector3f> grid(const Eigen::Vector3f& origin, const Eigen::Vector3f& step,
                                  int nx, int ny, int nz) {
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nz; ++k) {
        points.push_back(origin + Eigen::Vector3f(i * step.x(), j * step.y(), k * step.z()));
      }
    }
  }
  return points;
}

Cloud toCloud(const std::vector<Eigen::Vector3f>& points, std::uint8_t intensity = 0) {
  Cloud cloud;
  for (const Eigen::Vector3f& p : points) {
    cloud.push_back(PointXYZIT(p.x(), p.y(), p.z(), intensity, 0.0));
  }
  return cloud;
}

TEST(LalondeTest, PlaneLineAndBlobGiveTheirTextbookValues) {
  const auto plane = grid({0, 0, 0}, {0.1f, 0.1f, 0}, 11, 11, 1);  // equal spread in x and y
  const auto line = grid({0, 0, 0}, {0.1f, 0, 0}, 21, 1, 1);
  const auto blob = grid({0, 0, 0}, {0.1f, 0.1f, 0.1f}, 5, 5, 5);
  // The paper's definition, L1 = d1.
  const auto expect = [](const std::array<double, 3>& l, double l1, double l2, double l3,
                         const char* what) {
    EXPECT_NEAR(l[0], l1, 1e-6) << what;
    EXPECT_NEAR(l[1], l2, 1e-6) << what;
    EXPECT_NEAR(l[2], l3, 1e-6) << what;
  };
  expect(lalondeFeatures(plane, ScatterDefinition::kLargest), 0.5, 0.0, 0.5, "plane");
  expect(lalondeFeatures(line, ScatterDefinition::kLargest), 1.0, 1.0, 0.0, "line");
  expect(lalondeFeatures(blob, ScatterDefinition::kLargest), 1.0 / 3, 0.0, 0.0, "blob");
  // Lalonde et al.'s scatter-ness, L1 = d3: only the blob scatters.
  expect(lalondeFeatures(plane, ScatterDefinition::kSmallest), 0.0, 0.0, 0.5, "plane");
  expect(lalondeFeatures(line, ScatterDefinition::kSmallest), 0.0, 1.0, 0.0, "line");
  expect(lalondeFeatures(blob, ScatterDefinition::kSmallest), 1.0 / 3, 0.0, 0.0, "blob");
  // Too few points, or none spread: zeros, not NaN.
  expect(lalondeFeatures({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}}, ScatterDefinition::kSmallest), 0, 0,
         0, "one point thrice");
  expect(lalondeFeatures({{1, 2, 3}}, ScatterDefinition::kSmallest), 0, 0, 0, "one point");
}

TEST(PointHistogramTest, HasThePapersLayoutAndNormalisation) {
  const Cloud wall = toCloud(grid({0, -1, 0}, {0, 0.05f, 0.05f}, 1, 41, 41), 100);
  PointHistogramConfig config;
  const std::vector<float> features = pointHistogramFeatures(wall, config);
  ASSERT_EQ(features.size(), 60u);
  EXPECT_EQ(features[0], 100.0f);  // maximum intensity
  EXPECT_EQ(features[1], 100.0f);  // mean
  EXPECT_EQ(features[2], 0.0f);    // variance
  EXPECT_NEAR(features[3], 0.0f, 1e-6);  // a wall has no depth, so no volume
  // Every histogram sums to 1: each sample has neighbours and a cylinder.
  for (std::size_t h = 0; h < 8; ++h) {
    float sum = 0.0f;
    for (std::size_t b = 0; b < 7; ++b) {
      sum += features[4 + h * 7 + b];
    }
    EXPECT_NEAR(sum, 1.0f, 1e-4) << "histogram " << h;
  }
  // A wall is a surface: no scatter (bin 0 of L1), L3 = d2 - d3 high.
  EXPECT_NEAR(features[4 + 0], 1.0f, 1e-4);
}

TEST(PointHistogramTest, AWallPointFillsTheCylinderSlicesEqually) {
  // A wall 4 m high: columns 0.1 m apart, rows 1/15 m apart, so that a 1 m cylinder around
  // any point holds 3 rows of each of its five 0.2 m slices, none on a slice boundary.
  std::vector<Eigen::Vector3f> wall;
  for (int row = -30; row <= 30; ++row) {
    for (int column = -2; column <= 2; ++column) {
      wall.emplace_back(0.0f, 0.1f * column, 2.0f + row / 15.0f);
    }
  }
  PointHistogramConfig config;
  config.sample_points = wall.size();  // every point is a sample
  config.bins = 10;
  const std::vector<float> features = pointHistogramFeatures(toCloud(wall), config);
  ASSERT_EQ(features.size(), 4u + 8u * 10u);
  // Points more than 0.5 m from the wall's top and bottom (rows -22..22) have full cylinders:
  // exactly a fifth in each slice, bin 2 of 10.
  const std::size_t slices = 4 + 3 * 10;
  const float inner = 45.0f * 5 / wall.size();
  for (std::size_t slice = 0; slice < 5; ++slice) {
    EXPECT_GE(features[slices + slice * 10 + 2], inner - 1e-5) << "slice " << slice;
  }
  // All of the slice histograms against a brute-force count over every pair of points.
  std::vector<float> expected(5 * 10, 0.0f);
  for (const Eigen::Vector3f& centre : wall) {
    std::vector<int> counts(5, 0);
    int total = 0;
    for (const Eigen::Vector3f& p : wall) {
      const Eigen::Vector3f d = p - centre;
      if (d.head<2>().norm() <= 0.25f && std::abs(d.z()) <= 0.5f) {
        ++counts[std::min(4, static_cast<int>((d.z() + 0.5f) / 0.2f))];
        ++total;
      }
    }
    for (int slice = 0; slice < 5; ++slice) {
      const int bin = std::min(9, static_cast<int>(10.0 * counts[slice] / total));
      expected[slice * 10 + bin] += 1.0f / wall.size();
    }
  }
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_NEAR(features[slices + k], expected[k], 1e-5) << "slice " << k / 10 << " bin " << k % 10;
  }
  // One lone point: its cylinder holds only itself, in the middle slice.
  config.sample_points = 1;
  const std::vector<float> lone = pointHistogramFeatures(toCloud({{0, 0, 2}}), config);
  EXPECT_EQ(lone[slices + 2 * 10 + 9], 1.0f);  // middle slice: fraction 1, last bin
  EXPECT_EQ(lone[slices + 0 * 10 + 0], 1.0f);  // bottom slice: fraction 0, first bin
}

TEST(PointHistogramTest, TheLalondeHistogramsMatchABruteForceNearestSearch) {
  // Three walls, 1 m apart: 3, 8 and 20 cm between points, jittered by up to 2 mm so that no
  // two distances tie. A sample's 20 nearest then lie within a quarter or within three
  // quarters of the 0.5 m radius, or the sphere holds fewer than 20: each of the shells the
  // search ranks them in, and the whole sphere.
  std::mt19937 random(7);
  std::uniform_real_distribution<float> jitter(-0.002f, 0.002f);
  std::vector<Eigen::Vector3f> points;
  const auto wall = [&](float x, float spacing, int count) {
    for (int i = 0; i < count; ++i) {
      for (int j = 0; j < count; ++j) {
        points.emplace_back(x + jitter(random), i * spacing + jitter(random),
                            j * spacing + jitter(random));
      }
    }
  };
  wall(0.0f, 0.03f, 30);
  wall(1.0f, 0.08f, 12);
  wall(2.0f, 0.20f, 6);
  PointHistogramConfig config;
  config.sample_points = points.size();  // every point is a sample, in no random order
  const std::vector<float> features = pointHistogramFeatures(toCloud(points), config);

  const float radius = 0.5f;
  std::vector<float> expected(3 * 7, 0.0f);
  std::array<int, 3> twentieth_within{};  // a quarter, three quarters, beyond
  for (const Eigen::Vector3f& centre : points) {
    // Every point within the radius, nearest first (ties: the lower index first).
    std::vector<std::pair<float, std::size_t>> near;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Eigen::Vector3f d = points[k] - centre;
      const float squared = d.x() * d.x() + (d.y() * d.y() + d.z() * d.z());
      if (squared <= radius * radius) {
        near.emplace_back(squared, k);
      }
    }
    std::sort(near.begin(), near.end());
    near.resize(std::min<std::size_t>(near.size(), 20));
    const float twentieth = std::sqrt(near.back().first);
    ++twentieth_within[near.size() < 20 || twentieth > 0.75f * radius ? 2
                       : twentieth > 0.25f * radius                  ? 1
                                                                     : 0];
    std::vector<Eigen::Vector3f> neighbourhood;
    for (const auto& [squared, k] : near) {
      neighbourhood.push_back(points[k]);
    }
    const std::array<double, 3> lalonde = lalondeFeatures(neighbourhood, config.scatter);
    for (std::size_t f = 0; f < 3; ++f) {
      const auto bin = static_cast<std::size_t>(std::clamp(std::floor(lalonde[f] * 7), 0.0, 6.0));
      expected[f * 7 + bin] += 1.0f / points.size();
    }
  }
  for (const int samples : twentieth_within) {
    EXPECT_GT(samples, 20);
  }
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_NEAR(features[4 + k], expected[k], 1e-5) << "L" << k / 7 + 1 << " bin " << k % 7;
  }
}

TEST(ObjectFeaturesTest, MeanStdAndTinyObjectsAreNeverNan) {
  const Cloud box = toCloud({{1, 2, 0}, {3, 2, 2}});
  const std::vector<float> f = meanStdFeatures(box);
  const std::vector<float> expected = {2, 2, 1, 1, 0, 1};
  EXPECT_EQ(f, expected);
  for (const FeatureKind kind :
       {FeatureKind::kMeanStd, FeatureKind::kPointHistograms, FeatureKind::kEsf}) {
    for (const Cloud& cloud : {Cloud(), toCloud({{1, 1, 1}}), toCloud({{1, 1, 1}, {1, 2, 1}})}) {
      const std::vector<float> values = objectFeatures(cloud, kind);
      EXPECT_EQ(values.size(), featureSize(kind, PointHistogramConfig()));
      for (const float value : values) {
        EXPECT_TRUE(std::isfinite(value)) << featureKindName(kind);
      }
    }
  }
}

}  // namespace
}  // namespace granular
