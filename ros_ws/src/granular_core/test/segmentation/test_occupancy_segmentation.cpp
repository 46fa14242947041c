#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/segmentation/occupancy_segmentation.h"

namespace granular {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGroundZ = -2.0;  // m, the sensor 2 m above a flat road

struct Placed {
  Eigen::Vector2d centre;
  double yaw = 0.0;  // rad
  Eigen::Vector3d size;
  std::size_t first = 0, end = 0;  // its points are cloud[first, end)
};

void add(Cloud& cloud, const Eigen::Vector3d& p) {
  cloud.push_back(PointXYZIT(static_cast<float>(p.x()), static_cast<float>(p.y()),
                             static_cast<float>(p.z()), 0, 0.0));
}

// Ground points on a lattice of `step` over [-half, half)^2 at kGroundZ, each raised by up to
// +-noise.
void addGround(Cloud& cloud, double half, double step, double noise, std::mt19937& random) {
  std::uniform_real_distribution<double> jitter(-noise, noise);
  const int count = static_cast<int>(std::lround(2.0 * half / step));
  for (int i = 0; i < count; ++i) {
    for (int j = 0; j < count; ++j) {
      add(cloud, {-half + (i + 0.5) * step, -half + (j + 0.5) * step, kGroundZ + jitter(random)});
    }
  }
}

// Points on a lattice of about `step` on the four sides and the top of a box standing on the
// ground (no bottom face: the road).
Placed addBox(Cloud& cloud, const Eigen::Vector2d& centre, double yaw_deg,
              const Eigen::Vector3d& size, double step) {
  Placed box{centre, yaw_deg * kPi / 180.0, size, cloud.size(), 0};
  const Eigen::Rotation2Dd rotation(box.yaw);
  const auto put = [&](double u, double v, double z) {
    const Eigen::Vector2d xy = centre + rotation * Eigen::Vector2d(u, v);
    add(cloud, {xy.x(), xy.y(), kGroundZ + z});
  };
  const auto samples = [step](double length) {
    return static_cast<int>(std::ceil(length / step)) + 1;
  };
  const double l = size.x(), w = size.y(), h = size.z();
  const int nl = samples(l), nw = samples(w), nh = samples(h);
  for (int k = 0; k < nh; ++k) {
    const double z = h * k / (nh - 1);
    for (int i = 0; i < nl; ++i) {
      const double u = -l / 2 + l * i / (nl - 1);
      put(u, -w / 2, z);
      put(u, w / 2, z);
    }
    for (int j = 1; j + 1 < nw; ++j) {
      const double v = -w / 2 + w * j / (nw - 1);
      put(-l / 2, v, z);
      put(l / 2, v, z);
    }
  }
  for (int i = 1; i + 1 < nl; ++i) {
    for (int j = 1; j + 1 < nw; ++j) {
      put(-l / 2 + l * i / (nl - 1), -w / 2 + w * j / (nw - 1), h);
    }
  }
  box.end = cloud.size();
  return box;
}

// The segment whose centre is nearest to `where` in x-y.
const Segment& nearest(const std::vector<Segment>& segments, const Eigen::Vector2d& where) {
  return *std::min_element(segments.begin(), segments.end(),
                           [&](const Segment& a, const Segment& b) {
                             return (a.box.centre().head<2>() - where).norm() <
                                    (b.box.centre().head<2>() - where).norm();
                           });
}

// Angle between two headings modulo 180 degrees, in [0, 90].
double axisDifferenceDeg(double a, double b) {
  const double difference = std::abs(std::remainder(a - b, kPi));
  return difference * 180.0 / kPi;
}

bool contains(const std::vector<std::size_t>& sorted, std::size_t index) {
  return std::binary_search(sorted.begin(), sorted.end(), index);
}

// Signed distance of a point inside the footprint of the box whose sensorToObject() is
// `to_box`: positive inside, in metres.
double footprintMargin(const OrientedBox& box, const Eigen::Isometry3d& to_box,
                       const PointXYZIT& point) {
  const Eigen::Vector3d local = to_box * Eigen::Vector3d(point.x, point.y, point.z);
  return std::min(box.size().x() / 2 - std::abs(local.x()),
                  box.size().y() / 2 - std::abs(local.y()));
}

std::string validationMessage(const SegmentationConfig& config) {
  try {
    validate(config);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "accepted";
}

// ---- the scene of the brief: a car and a pillar on flat ground -----------------------------

class SegmentationSceneTest : public ::testing::Test {
 protected:
  static constexpr unsigned kSeed = 20240917;
  const ::testing::ScopedTrace trace_{__FILE__, __LINE__,
                                      "random seed " + std::to_string(kSeed)};
  std::mt19937 random_{kSeed};

  void SetUp() override {
    addGround(cloud_, 15.0, 0.1, 0.01, random_);  // 90,000 points
    ground_end_ = cloud_.size();
    car_ = addBox(cloud_, {10.0, 5.0}, 30.0, {4.0, 2.0, 1.5}, 0.05);
    pillar_ = addBox(cloud_, {-8.0, -6.0}, 0.0, {1.0, 1.0, 2.0}, 0.05);
  }

  Cloud cloud_;
  std::size_t ground_end_ = 0;
  Placed car_, pillar_;
};

TEST_F(SegmentationSceneTest, FindsTheCarAndThePillar) {
  const std::vector<Segment> segments = segmentCloud(cloud_);
  ASSERT_EQ(segments.size(), 2u);
  for (const Placed* truth : {&car_, &pillar_}) {
    SCOPED_TRACE("object at (" + std::to_string(truth->centre.x()) + ", " +
                 std::to_string(truth->centre.y()) + ")");
    const Segment& segment = nearest(segments, truth->centre);
    const OrientedBox& box = segment.box;
    EXPECT_LT((box.centre().head<2>() - truth->centre).norm(), 0.2);
    // The footprint encloses the cells the object touches, so it is larger than the object:
    // on each side by the overhang of the outermost cell centres, up to r = (cell / 2) *
    // (|cos yaw| + |sin yaw|), plus the margin r that encloses those cells. At 30 degrees
    // r = 0.10 m; the car comes out 0.39 m longer and 0.37 m wider than the truth.
    const double r = 0.5 * SegmentationConfig().cell_size *
                     (std::abs(std::cos(truth->yaw)) + std::abs(std::sin(truth->yaw)));
    EXPECT_GE(box.size().x(), truth->size.x()) << "length";
    EXPECT_LE(box.size().x(), truth->size.x() + 4.0 * r) << "length";
    EXPECT_GE(box.size().y(), truth->size.y()) << "width";
    EXPECT_LE(box.size().y(), truth->size.y() + 4.0 * r) << "width";
    // Bottom on the noisy ground, top at the object's roof.
    EXPECT_NEAR(box.centre().z() - box.size().z() / 2, kGroundZ, 0.0101);
    EXPECT_NEAR(box.centre().z() + box.size().z() / 2, kGroundZ + truth->size.z(), 1e-5);
    EXPECT_GT(segment.cells, 0u);

    // indices: sorted, unique, exactly the points of the footprint (edges within 0.1 mm),
    // hence every point of the object.
    EXPECT_TRUE(std::is_sorted(segment.indices.begin(), segment.indices.end()));
    EXPECT_EQ(std::adjacent_find(segment.indices.begin(), segment.indices.end()),
              segment.indices.end());
    const Eigen::Isometry3d to_box = box.sensorToObject();
    for (std::size_t i = 0; i < cloud_.size(); ++i) {
      const double margin = footprintMargin(box, to_box, cloud_[i]);
      if (margin > 1e-4) {
        ASSERT_TRUE(contains(segment.indices, i)) << "point " << i << " inside by " << margin;
      } else if (margin < -1e-4) {
        ASSERT_FALSE(contains(segment.indices, i)) << "point " << i << " outside by " << margin;
      }
    }
    for (std::size_t i = truth->first; i < truth->end; ++i) {
      ASSERT_TRUE(contains(segment.indices, i)) << "object point " << i;
    }
  }

  const Segment& car = nearest(segments, car_.centre);
  EXPECT_LT(axisDifferenceDeg(car.box.yaw(), car_.yaw), 3.0) << "yaw " << car.box.yaw();
  EXPECT_GT(car.box.size().x(), car.box.size().y());
  for (std::size_t i = pillar_.first; i < pillar_.end; ++i) {
    ASSERT_FALSE(contains(car.indices, i)) << "pillar point " << i << " in the car";
  }
  const Segment& pillar = nearest(segments, pillar_.centre);
  for (std::size_t i = car_.first; i < car_.end; ++i) {
    ASSERT_FALSE(contains(pillar.indices, i)) << "car point " << i << " in the pillar";
  }
  // Row-major scan order: the pillar (y = -6) comes first.
  EXPECT_EQ(&pillar, &segments[0]);
}

TEST_F(SegmentationSceneTest, IgnoresNonFinitePoints) {
  const std::size_t count = cloud_.size();
  cloud_.push_back(PointXYZIT(NAN, 5.0f, 0.0f, 0, 0.0));
  cloud_.push_back(PointXYZIT(10.0f, 5.0f, INFINITY, 0, 0.0));
  cloud_.push_back(PointXYZIT(10.0f, -INFINITY, 0.0f, 0, 0.0));
  const std::vector<Segment> segments = segmentCloud(cloud_);
  ASSERT_EQ(segments.size(), 2u);
  for (const Segment& segment : segments) {
    EXPECT_LT(segment.indices.back(), count);
  }
}

TEST_F(SegmentationSceneTest, GroundAloneGivesNoSegments) {
  cloud_.resize(ground_end_);
  EXPECT_TRUE(segmentCloud(cloud_).empty());
}

TEST(SegmentationTest, EmptyCloudGivesNoSegments) {
  EXPECT_TRUE(segmentCloud(Cloud()).empty());
  Cloud invalid;
  invalid.push_back(PointXYZIT(NAN, NAN, NAN, 0, 0.0));
  EXPECT_TRUE(segmentCloud(invalid).empty());
}

TEST(SegmentationTest, IgnoresPointsOutsideTheExtent) {
  Cloud cloud;
  addBox(cloud, {60.0, 0.0}, 0.0, {1.0, 1.0, 2.0}, 0.05);  // x beyond extent / 2 = 50
  addBox(cloud, {0.0, -51.0}, 0.0, {1.0, 1.0, 2.0}, 0.05);
  EXPECT_TRUE(segmentCloud(cloud).empty());
  SegmentationConfig wide;
  wide.extent = 200.0;
  EXPECT_EQ(segmentCloud(cloud, wide).size(), 2u);
}

TEST(SegmentationTest, DropsSmallAndLongComponents) {
  Cloud cloud;
  // A pole inside the one cell [-0.05, 0.1)^2: a single occupied cell.
  for (int k = 0; k <= 10; ++k) {
    add(cloud, {0.07, 0.07, kGroundZ + 0.1 * k});
  }
  addBox(cloud, {0.0, 20.0}, 0.0, {30.0, 0.2, 1.0}, 0.05);  // a wall
  SegmentationConfig config;
  EXPECT_TRUE(segmentCloud(cloud, config).empty());

  config.min_cells = 1;
  config.max_length = std::numeric_limits<double>::infinity();
  const std::vector<Segment> segments = segmentCloud(cloud, config);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_EQ(segments[0].cells, 1u);
  EXPECT_EQ(segments[0].indices.size(), 11u);
  EXPECT_NEAR(segments[0].box.size().x(), 0.15, 1e-9);
  EXPECT_NEAR(segments[0].box.size().z(), 1.0, 1e-6);
  EXPECT_NEAR(segments[1].box.size().x(), 30.0, 0.45);

  config.min_points = 12;
  EXPECT_EQ(segmentCloud(cloud, config).size(), 1u);
}

TEST(SegmentationTest, ValidateNamesTheField) {
  EXPECT_EQ(validationMessage(SegmentationConfig()), "accepted");
  const auto with = [](auto change) {
    SegmentationConfig config;
    change(config);
    return validationMessage(config);
  };
  EXPECT_NE(with([](auto& c) { c.cell_size = 0.0; }).find("cell_size"), std::string::npos);
  EXPECT_NE(with([](auto& c) { c.cell_size = -0.15; }).find("cell_size"), std::string::npos);
  EXPECT_NE(with([](auto& c) { c.cell_size = NAN; }).find("cell_size"), std::string::npos);
  EXPECT_NE(with([](auto& c) { c.extent = 0.0; }).find("extent"), std::string::npos);
  EXPECT_NE(with([](auto& c) { c.cell_size = 0.001; }).find("cells a side"), std::string::npos);
  EXPECT_NE(with([](auto& c) { c.height_threshold = -0.1; }).find("height_threshold"),
            std::string::npos);
  EXPECT_NE(with([](auto& c) { c.min_cells = 0; }).find("min_cells"), std::string::npos);
  EXPECT_NE(with([](auto& c) { c.max_length = 0.0; }).find("max_length"), std::string::npos);

  SegmentationConfig bad;
  bad.cell_size = 0.0;
  EXPECT_THROW(segmentCloud(Cloud(), bad), std::invalid_argument);
}

// ---- matching ------------------------------------------------------------------------------

OrientedBox boxAt(double x, double y) {
  return OrientedBox({x, y, 0.0}, Eigen::Quaterniond::Identity(), {4.0, 2.0, 1.5});
}

TEST(MatchSegmentsTest, CountsAKnownCase) {
  const std::vector<OrientedBox> truth = {boxAt(0, 0), boxAt(5, 0), boxAt(10, 0)};
  const std::vector<OrientedBox> segments = {boxAt(0.5, 0), boxAt(0, 0.3), boxAt(5, 0.9),
                                             boxAt(20, 0)};
  // (0, 0) takes the nearer (0, 0.3); (0.5, 0) is left over; (5, 0) takes (5, 0.9); (10, 0)
  // has no segment within 1 m.
  SegmentationMatch match = matchSegments(segments, truth);
  EXPECT_EQ(match.truth, 3u);
  EXPECT_EQ(match.matched_truth, 2u);
  EXPECT_EQ(match.segments, 4u);
  EXPECT_EQ(match.unmatched_segments, 2u);

  match = matchSegments(segments, truth, 0.5);  // (5, 0.9) is too far now
  EXPECT_EQ(match.matched_truth, 1u);
  EXPECT_EQ(match.unmatched_segments, 3u);

  EXPECT_EQ(matchSegments({}, truth).matched_truth, 0u);
  EXPECT_EQ(matchSegments(segments, {}).unmatched_segments, 4u);
  EXPECT_THROW(matchSegments(segments, truth, -1.0), std::invalid_argument);
}

TEST(MatchSegmentsTest, NearestPairsGoFirst) {
  // The segment at 0.6 is 0.6 from truth 0 and 0.4 from truth 1: it goes to truth 1, and
  // truth 0 is left without, though a one-to-one assignment of both would exist.
  const std::vector<OrientedBox> truth = {boxAt(0, 0), boxAt(1, 0)};
  const SegmentationMatch match = matchSegments({boxAt(0.6, 0), boxAt(1.9, 0)}, truth);
  EXPECT_EQ(match.matched_truth, 1u);
  EXPECT_EQ(match.unmatched_segments, 1u);
}

}  // namespace
}  // namespace granular
