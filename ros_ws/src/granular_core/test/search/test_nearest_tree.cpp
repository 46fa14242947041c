// NearestTree: what PCL's KdTreeFLANN answers (the nearest point, the fitness score), checked
// against brute force on random points, with and without a correspondence bound.
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/common/transforms.h>

#include "granular_core/search/nearest_points.h"
#include "granular_core/search/nearest_tree.h"
#include "support/brute_force.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::boxSurface;
using testing_support::bruteNearest;
using testing_support::xyzOf;

// A car-sized surface, and queries near it and far from it.
class NearestTreeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(23);
    model_.reset(new ModelCloud(boxSurface({4.5, 1.8, 1.5}, 2000, random)));
    points_ = xyzOf(*model_);
    std::uniform_real_distribution<float> near(-3.0f, 3.0f);
    std::uniform_real_distribution<float> far(-15.0f, 15.0f);
    for (int i = 0; i < 3000; ++i) {
      auto& distribution = i % 4 == 0 ? far : near;
      queries_.push_back(
          pcl::PointXYZ(distribution(random), distribution(random), distribution(random)));
    }
  }

  float brute(const pcl::PointXYZ& query, float bound) const {
    return bruteNearest(points_, query.data, bound);
  }

  ModelCloud::Ptr model_;
  std::vector<float> points_;
  ModelCloud queries_;
};

TEST_F(NearestTreeTest, TheNearestPointIsBruteForcesToTheBit) {
  NearestTree tree;
  tree.setInputCloud(model_);
  pcl::Indices indices;
  std::vector<float> distances;
  for (const pcl::PointXYZ& query : queries_) {
    const float expected = brute(query, std::numeric_limits<float>::infinity());
    ASSERT_EQ(tree.nearestKSearch(query, 1, indices, distances), 1);
    EXPECT_EQ(distances[0], expected);
    EXPECT_EQ(flannSquaredDistance(query.data, &points_[3 * indices[0]]), expected);
    const NearestTree::Neighbour neighbour = tree.nearestWithinBound(query);
    ASSERT_TRUE(neighbour.found);  // no bound: always a neighbour
    EXPECT_EQ(neighbour.squared, expected);
    EXPECT_EQ(neighbour.index, indices[0]);
  }
}

TEST_F(NearestTreeTest, ACorrespondenceBoundHidesTheNeighboursBeyondIt) {
  NearestTree tree;
  tree.setCorrespondenceBound(0.1);  // m
  tree.setInputCloud(model_);
  // Beside the random queries, model points moved by a few centimetres: most within the bound.
  ModelCloud queries = queries_;
  std::mt19937 random(29);
  std::normal_distribution<float> jitter(0.0f, 0.05f);
  for (std::size_t i = 0; i < model_->size(); i += 10) {
    const pcl::PointXYZ& p = (*model_)[i];
    queries.push_back(pcl::PointXYZ(p.x + jitter(random), p.y + jitter(random),
                                    p.z + jitter(random)));
  }
  int found = 0, hidden = 0;
  for (const pcl::PointXYZ& query : queries) {
    const float expected = brute(query, std::numeric_limits<float>::infinity());
    const NearestTree::Neighbour neighbour = tree.nearestWithinBound(query);
    if (expected <= 0.01f) {
      ASSERT_TRUE(neighbour.found);
      EXPECT_EQ(neighbour.squared, expected);
      ++found;
    } else if (expected > 0.0101f) {  // clear of the bound's float rounding
      EXPECT_FALSE(neighbour.found) << expected;
      ++hidden;
    }
  }
  EXPECT_GT(found, 100);  // of the 200 moved model points
  EXPECT_GT(hidden, 2000);
}

TEST_F(NearestTreeTest, TheFitnessIsTheMeanSquaredNearestDistanceOfTheMovedSource) {
  NearestTree tree;
  tree.setInputCloud(model_);
  tree.buildFitnessBound(0.5f, 1.0f);
  std::mt19937 random(5);
  const ModelCloud source = boxSurface({4.3, 1.7, 1.4}, 500, random);
  const Eigen::Affine3f motion = Eigen::Translation3f(0.3f, -0.1f, 0.05f) *
                                 Eigen::AngleAxisf(0.1f, Eigen::Vector3f::UnitZ());
  ModelCloud moved;
  pcl::transformPointCloud(source, moved, motion);
  double sum = 0.0;
  for (const pcl::PointXYZ& point : moved) {
    sum += brute(point, std::numeric_limits<float>::infinity());
  }
  const double expected = sum / static_cast<double>(moved.size());
  EXPECT_EQ(tree.fitness(source, motion.matrix()), expected);
  EXPECT_EQ(tree.fitnessOfMoved(moved), expected);
  const double lower = tree.fitnessLowerBound(moved);
  EXPECT_GT(lower, 0.0);
  EXPECT_LE(lower, expected);

  NearestTree empty;
  empty.setInputCloud(ModelCloud::Ptr(new ModelCloud));
  EXPECT_EQ(empty.fitness(source, motion.matrix()), std::numeric_limits<double>::max());
  EXPECT_EQ(tree.fitnessOfMoved(ModelCloud()), std::numeric_limits<double>::max());
}

}  // namespace
}  // namespace granular
