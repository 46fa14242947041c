// Cropping detections into object frames.
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "granular_core/extraction/extract_objects.h"

namespace granular {
namespace {

constexpr double kTolerance = 1e-4;  // metres; float storage of ~10 m coordinates is ~1e-6

Eigen::Quaterniond yawPitchRoll(double yaw, double pitch, double roll) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

Detection makeDetection(const std::string& label, const Eigen::Vector3d& centre,
                        const Eigen::Quaterniond& orientation, const Eigen::Vector3d& size) {
  Detection detection;
  detection.id = 7;
  detection.label = label;
  detection.centre = centre;
  detection.orientation = orientation;
  detection.size = size;
  return detection;
}

// The sensor-frame position of an object-frame point of `detection` (independent of
// OrientedBox: built from the raw detection fields).
Eigen::Vector3d toSensor(const Detection& detection, const Eigen::Vector3d& object_point) {
  const Eigen::Vector3d box_point = object_point - Eigen::Vector3d(0, 0, detection.size.z() / 2);
  return detection.orientation.normalized() * box_point + detection.centre;
}

PointXYZIT makePoint(const Eigen::Vector3d& p, std::uint8_t intensity, double timestamp) {
  return PointXYZIT(static_cast<float>(p.x()), static_cast<float>(p.y()),
                    static_cast<float>(p.z()), intensity, timestamp);
}

class TiltedBoxTest : public ::testing::Test {
 protected:
  // Yawed, pitched and rolled, away from the origin.
  const Detection detection_ = makeDetection("Sedan", Eigen::Vector3d(12.0, -4.0, -1.2),
                                             yawPitchRoll(0.7, 0.25, -0.15),
                                             Eigen::Vector3d(4.5, 1.9, 1.5));
};

TEST_F(TiltedBoxTest, ExtractsExactlyTheInsidePointsAtTheirObjectFrameCoordinates) {
  const unsigned seed = 20240611;
  SCOPED_TRACE("random seed " + std::to_string(seed));
  std::mt19937 random(seed);
  const Eigen::Vector3d half = detection_.size / 2;
  const double margin = 1e-3;  // keep generated points clear of the faces
  std::uniform_real_distribution<double> unit(-1.0, 1.0);

  Cloud cloud;
  std::map<double, Eigen::Vector3d> expected;  // timestamp -> object-frame point
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d object(unit(random) * (half.x() - margin),
                                 unit(random) * (half.y() - margin),
                                 half.z() + unit(random) * (half.z() - margin));
    const double timestamp = 1000.0 + i;
    cloud.push_back(makePoint(toSensor(detection_, object), static_cast<std::uint8_t>(i % 256),
                              timestamp));
    expected[timestamp] = object;
  }
  // Just outside each face, and points that only the axis-aligned hull would catch.
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {-1.0, 1.0}) {
      Eigen::Vector3d object(0.0, 0.0, half.z());
      object[axis] += side * (half[axis] + 0.01);
      cloud.push_back(makePoint(toSensor(detection_, object), 0, -1.0));
    }
  }
  cloud.push_back(makePoint(detection_.centre + Eigen::Vector3d(2.3, 1.2, 0.9), 0, -1.0));
  cloud.push_back(makePoint(Eigen::Vector3d(0.0, 0.0, 0.0), 0, -1.0));

  const FrameExtraction result = extractObjects(cloud, {detection_}, ExtractionConfig());
  ASSERT_TRUE(result.errors.empty());
  ASSERT_EQ(result.objects.size(), 1u);
  const Cloud& object = result.objects[0].cloud;
  ASSERT_EQ(object.size(), expected.size());
  EXPECT_EQ(object.width, object.size());
  EXPECT_EQ(object.height, 1u);
  for (const PointXYZIT& point : object.points) {
    const auto match = expected.find(point.timestamp);
    ASSERT_NE(match, expected.end()) << "unexpected point with timestamp " << point.timestamp;
    EXPECT_NEAR(point.x, match->second.x(), kTolerance);
    EXPECT_NEAR(point.y, match->second.y(), kTolerance);
    EXPECT_NEAR(point.z, match->second.z(), kTolerance);
    const int index = static_cast<int>(point.timestamp - 1000.0);
    EXPECT_EQ(point.intensity, static_cast<std::uint8_t>(index % 256));
  }
}

TEST_F(TiltedBoxTest, FaceCentresMapToTheObjectFrameConvention) {
  const OrientedBox box(detection_.centre, detection_.orientation, detection_.size);
  const Eigen::Vector3d& size = detection_.size;
  const Eigen::Isometry3d to_object = box.sensorToObject();

  const Eigen::Vector3d front_in_object(size.x() / 2, 0, size.z() / 2);
  const Eigen::Vector3d front = toSensor(detection_, front_in_object);
  EXPECT_TRUE((to_object * front).isApprox(front_in_object, 1e-12));
  const Eigen::Vector3d bottom = toSensor(detection_, Eigen::Vector3d::Zero());
  EXPECT_LT((to_object * bottom).norm(), 1e-12);
  EXPECT_LT((to_object * detection_.centre - Eigen::Vector3d(0, 0, size.z() / 2)).norm(), 1e-12);

  // Through the crop as well; a millimetre of padding keeps float rounding from putting the
  // face points a hair outside.
  Cloud cloud;
  cloud.push_back(makePoint(front, 1, 1.0));
  cloud.push_back(makePoint(bottom, 2, 2.0));
  const Cloud object = cropToObjectFrame(cloud, box, Eigen::Vector3d::Constant(1e-3));
  ASSERT_EQ(object.size(), 2u);
  EXPECT_NEAR(object[0].x, size.x() / 2, kTolerance);
  EXPECT_NEAR(object[0].y, 0.0, kTolerance);
  EXPECT_NEAR(object[0].z, size.z() / 2, kTolerance);
  EXPECT_NEAR(object[1].x, 0.0, kTolerance);
  EXPECT_NEAR(object[1].y, 0.0, kTolerance);
  EXPECT_NEAR(object[1].z, 0.0, kTolerance);
}

TEST_F(TiltedBoxTest, PaddingGrowsEachSideAlongTheBoxAxes) {
  const OrientedBox box(detection_.centre, detection_.orientation, detection_.size);
  Cloud cloud;
  cloud.push_back(makePoint(toSensor(detection_, Eigen::Vector3d(0, detection_.size.y() / 2 + 0.1,
                                                                 detection_.size.z() / 2)),
                            0, 0.0));
  EXPECT_EQ(cropToObjectFrame(cloud, box, Eigen::Vector3d::Zero()).size(), 0u);
  EXPECT_EQ(cropToObjectFrame(cloud, box, Eigen::Vector3d(0.0, 0.05, 0.0)).size(), 0u);
  EXPECT_EQ(cropToObjectFrame(cloud, box, Eigen::Vector3d(0.0, 0.2, 0.0)).size(), 1u);
  EXPECT_EQ(cropToObjectFrame(cloud, box, Eigen::Vector3d(0.2, 0.0, 0.2)).size(), 0u);
}

TEST_F(TiltedBoxTest, InvalidDetectionsAreReportedAndSkipped) {
  Detection zero_size = detection_;
  zero_size.label = "Zero";
  zero_size.size.y() = 0.0;
  Detection zero_quaternion = detection_;
  zero_quaternion.label = "NoRotation";
  zero_quaternion.orientation = Eigen::Quaterniond(0, 0, 0, 0);

  Cloud cloud;
  cloud.push_back(makePoint(detection_.centre, 0, 0.0));
  const FrameExtraction result =
      extractObjects(cloud, {zero_size, detection_, zero_quaternion}, ExtractionConfig());
  ASSERT_EQ(result.errors.size(), 2u);
  EXPECT_NE(result.errors[0].find("detections[0] (id 7, Zero)"), std::string::npos)
      << result.errors[0];
  EXPECT_NE(result.errors[0].find("size"), std::string::npos) << result.errors[0];
  EXPECT_NE(result.errors[1].find("detections[2] (id 7, NoRotation)"), std::string::npos)
      << result.errors[1];
  EXPECT_NE(result.errors[1].find("quaternion"), std::string::npos) << result.errors[1];
  ASSERT_EQ(result.objects.size(), 1u);
  EXPECT_EQ(result.objects[0].cloud.size(), 1u);
}

TEST_F(TiltedBoxTest, BoxesBeyondMaxBoxSizeAreSkippedWithTheirSize) {
  Detection huge = detection_;
  huge.label = "Wall";
  huge.size.x() = 1e30;
  Detection at_bound = detection_;
  at_bound.size.z() = 30.0;  // as large as the bound allows

  Cloud cloud;
  cloud.push_back(makePoint(detection_.centre, 0, 0.0));
  const FrameExtraction result =
      extractObjects(cloud, {huge, at_bound}, ExtractionConfig());  // max_box_size 30 m
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_EQ(result.errors[0],
            "detections[0] (id 7, Wall): box of 1e+30 x 1.9 x 1.5 m is larger than "
            "max_box_size (30 m): implausible");
  ASSERT_EQ(result.objects.size(), 1u);
  EXPECT_EQ(result.objects[0].box.size().z(), 30.0);
}

TEST_F(TiltedBoxTest, NonUnitQuaternionGivesTheNormalisedResult) {
  Detection scaled = detection_;
  scaled.orientation.coeffs() *= 3.7;
  Cloud cloud;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> around(-3.0f, 3.0f);
  for (int i = 0; i < 2000; ++i) {
    cloud.push_back(PointXYZIT(12.0f + around(random), -4.0f + around(random),
                               -1.2f + around(random), 0, i));
  }
  const FrameExtraction a = extractObjects(cloud, {detection_}, ExtractionConfig());
  const FrameExtraction b = extractObjects(cloud, {scaled}, ExtractionConfig());
  ASSERT_TRUE(b.errors.empty());
  ASSERT_EQ(a.objects[0].cloud.size(), b.objects[0].cloud.size());
  ASSERT_GT(a.objects[0].cloud.size(), 100u);
  for (std::size_t i = 0; i < a.objects[0].cloud.size(); ++i) {
    EXPECT_EQ(a.objects[0].cloud[i].timestamp, b.objects[0].cloud[i].timestamp);
    EXPECT_NEAR(a.objects[0].cloud[i].x, b.objects[0].cloud[i].x, 1e-6);
    EXPECT_NEAR(a.objects[0].cloud[i].y, b.objects[0].cloud[i].y, 1e-6);
    EXPECT_NEAR(a.objects[0].cloud[i].z, b.objects[0].cloud[i].z, 1e-6);
  }
}

TEST_F(TiltedBoxTest, NonFinitePointsAreSkippedAndCounted) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Cloud cloud;
  cloud.push_back(makePoint(detection_.centre, 0, 1.0));
  cloud.push_back(PointXYZIT(nan, -4.0f, -1.2f, 0, 2.0));
  cloud.push_back(PointXYZIT(12.0f, nan, -1.2f, 0, 3.0));
  cloud.push_back(PointXYZIT(12.0f, -4.0f, inf, 0, 4.0));
  cloud.push_back(PointXYZIT(-inf, -4.0f, -1.2f, 0, 5.0));
  const FrameExtraction result = extractObjects(cloud, {detection_}, ExtractionConfig());
  EXPECT_EQ(result.non_finite_points, 4u);
  ASSERT_EQ(result.objects.size(), 1u);
  ASSERT_EQ(result.objects[0].cloud.size(), 1u);
  EXPECT_EQ(result.objects[0].cloud[0].timestamp, 1.0);
}

TEST_F(TiltedBoxTest, LabelFilterKeepsPerLabelIndices) {
  Detection suv = detection_;
  suv.label = "SUV";
  ExtractionConfig config;
  config.labels = {"Sedan"};
  const FrameExtraction result = extractObjects(Cloud(), {detection_, suv, detection_}, config);
  ASSERT_EQ(result.objects.size(), 2u);
  EXPECT_EQ(result.objects[0].label_index, 1u);
  EXPECT_EQ(result.objects[1].label_index, 2u);
  EXPECT_EQ(result.objects[1].detection.label, "Sedan");

  const FrameExtraction all = extractObjects(Cloud(), {detection_, suv, detection_}, {});
  ASSERT_EQ(all.objects.size(), 3u);
  EXPECT_EQ(all.objects[1].label_index, 1u);
  EXPECT_EQ(all.objects[2].label_index, 2u);
}

// A box-free cuboid's heading is known modulo 180 degrees: fitted either way round, the car's
// end away from the sensor must come out at the object frame's front (+x), on either side of
// the sensor, or a classifier that learnt objects so turned sees half of them reversed.
TEST(FacingAwayFromSensorTest, CropsACuboidFittedEitherWayRoundWithItsFarEndInFront) {
  for (const double side : {1.0, -1.0}) {  // ahead of the sensor, then behind it
    const Eigen::Vector3d centre(side * 10.0, 3.0, -1.0);
    const Eigen::Vector3d along = Eigen::Vector3d::UnitX();  // the car's length axis
    Cloud cloud;
    cloud.push_back(makePoint(centre + side * 2.0 * along, 1, 0.0));  // far end
    cloud.push_back(makePoint(centre - side * 2.0 * along, 2, 0.0));  // near end
    for (const double yaw : {0.0, M_PI}) {
      SCOPED_TRACE("side " + std::to_string(side) + ", yaw " + std::to_string(yaw));
      const Detection fitted = makeDetection("unknown", centre, yawPitchRoll(yaw, 0.0, 0.0),
                                             Eigen::Vector3d(4.5, 1.9, 1.5));
      const Detection away = facingAwayFromSensor(fitted);
      EXPECT_EQ(away.centre, fitted.centre);
      EXPECT_EQ(away.size, fitted.size);
      const FrameExtraction result = extractObjects(cloud, {away}, ExtractionConfig());
      ASSERT_EQ(result.objects.size(), 1u);
      ASSERT_EQ(result.objects[0].cloud.size(), 2u);
      EXPECT_EQ(result.objects[0].cloud[0].intensity, 1);
      EXPECT_NEAR(result.objects[0].cloud[0].x, 2.0, kTolerance);
      EXPECT_NEAR(result.objects[0].cloud[1].x, -2.0, kTolerance);
    }
  }
}

TEST(FrameCropperTest, CropsTheSamePointsInTheSameOrderAsTheWholeCloudScan) {
  // A street-sized cloud with non-finite points and a far stray one, and boxes of every
  // orientation and size, some padded, some off the cloud or on cell borders: each crop must
  // equal cropToObjectFrame's, point for point.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> across(-40.0, 40.0), up(-2.0, 3.0), unit(0.0, 1.0);
  Cloud cloud;
  for (int i = 0; i < 30000; ++i) {
    cloud.push_back(PointXYZIT(static_cast<float>(across(random)),
                               static_cast<float>(across(random)),
                               static_cast<float>(up(random)), static_cast<std::uint8_t>(i % 256),
                               static_cast<double>(i)));
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cloud.push_back(PointXYZIT(nan, 1.0f, 0.0f, 0, 0.0));
  cloud.push_back(PointXYZIT(3.0f, std::numeric_limits<float>::infinity(), 0.0f, 0, 0.0));
  cloud.push_back(PointXYZIT(5000.0f, -3000.0f, 0.0f, 0, 0.0));
  const FrameCropper cropper(cloud);
  std::size_t cropped = 0;
  for (int b = 0; b < 300; ++b) {
    const Eigen::Vector3d centre(b % 7 == 0 ? std::round(across(random)) : across(random) * 1.2,
                                 across(random) * 1.2, up(random));
    const Eigen::Vector3d size(0.2 + 12.0 * unit(random), 0.2 + 3.0 * unit(random),
                               0.5 + 3.0 * unit(random));
    const OrientedBox box(centre,
                          yawPitchRoll(6.3 * unit(random), 0.3 * unit(random), 0.3 * unit(random)),
                          size);
    const Eigen::Vector3d padding = Eigen::Vector3d::Constant(b % 3 == 0 ? 0.5 : 0.0);
    const Cloud expected = cropToObjectFrame(cloud, box, padding);
    const Cloud got = cropper.crop(box, padding);
    ASSERT_EQ(got.size(), expected.size()) << "box " << b;
    for (std::size_t i = 0; i < got.size(); ++i) {
      ASSERT_EQ(got[i].timestamp, expected[i].timestamp) << "box " << b << ", point " << i;
      ASSERT_EQ(got[i].x, expected[i].x);
    }
    cropped += got.size();
  }
  EXPECT_GT(cropped, 3000u);  // the boxes held points (5,427)
  // A stray box far from every point, and a cloud without a finite point, crop nothing.
  EXPECT_TRUE(cropper.crop(OrientedBox(Eigen::Vector3d(-900.0, 900.0, 0.0),
                                       Eigen::Quaterniond::Identity(), Eigen::Vector3d::Ones()),
                           Eigen::Vector3d::Zero())
                  .empty());
  Cloud nothing;
  nothing.push_back(PointXYZIT(nan, nan, nan, 0, 0.0));
  EXPECT_TRUE(FrameCropper(nothing)
                  .crop(OrientedBox(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(),
                                    Eigen::Vector3d::Ones()),
                        Eigen::Vector3d::Zero())
                  .empty());
}

TEST(FrameCropperTest, KeepsThePointsOnABoxsFacesWhereTheyMeetCellBorders) {
  // 1 m cells from the lowest point (0, 0): the box's x-y faces lie on cell borders, and a
  // point on a face (inside, as the whole scan counts it) lies in the cell beyond the face, so
  // cells chosen from bounds a hair too narrow would miss it.
  Cloud cloud;
  cloud.push_back(PointXYZIT(0.0f, 0.0f, 0.0f, 0, 0.0));
  for (const float x : {2.0f, 2.5f, 4.0f}) {
    for (const float y : {1.0f, 1.5f, 3.0f}) {
      cloud.push_back(PointXYZIT(x, y, 0.5f, 0, 0.0));
    }
  }
  cloud.push_back(PointXYZIT(9.0f, 9.0f, 0.0f, 0, 0.0));
  const OrientedBox box(Eigen::Vector3d(3.0, 2.0, 0.5), Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(2.0, 2.0, 1.0));
  ASSERT_EQ(cropToObjectFrame(cloud, box, Eigen::Vector3d::Zero()).size(), 9u);
  const Cloud got = FrameCropper(cloud).crop(box, Eigen::Vector3d::Zero());
  ASSERT_EQ(got.size(), 9u);
  EXPECT_FLOAT_EQ(got[8].x, 1.0f);  // (4, 3): the far corner, in the object frame
  EXPECT_FLOAT_EQ(got[8].y, 1.0f);
}

}  // namespace
}  // namespace granular
