// ICP-NL's step with analytic Jacobians: it recovers a known motion, finds the closed-form
// least-squares motion (Umeyama's) of noisy pairs, and lands where PCL's numerical
// Levenberg-Marquardt does, within that one's float tolerance.
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <pcl/point_types.h>
#include <pcl/registration/transformation_estimation_lm.h>

#include "granular_core/registration/point_to_point_lm.h"

namespace granular {
namespace {

struct Pairs {
  std::vector<Eigen::Vector3d> source, target;
};

// Points of a car-sized box's volume, and where `motion` takes them, with noise of `sigma` m.
Pairs pairs(const Eigen::Isometry3d& motion, double sigma, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> x(-2.2, 2.2), y(-0.9, 0.9), z(0.0, 1.5);
  std::normal_distribution<double> noise(0.0, sigma);
  Pairs result;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d point(x(random), y(random), z(random));
    result.source.push_back(point);
    result.target.push_back(motion * point +
                            Eigen::Vector3d(noise(random), noise(random), noise(random)));
  }
  return result;
}

Eigen::Isometry3d motion(double yaw, double pitch, const Eigen::Vector3d& shift) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  m.translation() = shift;
  return m;
}

double difference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

TEST(PointToPointLmTest, RecoversAKnownMotionExactly) {
  const Eigen::Isometry3d truth = motion(0.3, -0.05, {0.4, -0.2, 0.1});
  const Pairs exact = pairs(truth, 0.0, 1);
  EXPECT_LT(difference(pointToPointLm(exact.source, exact.target).matrix(), truth.matrix()),
            1e-9);
}

TEST(PointToPointLmTest, NoisyPairsGiveTheLeastSquaresMotion) {
  const Pairs noisy = pairs(motion(-0.2, 0.02, {-0.3, 0.1, 0.0}), 0.05, 2);
  Eigen::Matrix3Xd from(3, noisy.source.size()), to(3, noisy.target.size());
  for (std::size_t i = 0; i < noisy.source.size(); ++i) {
    from.col(i) = noisy.source[i];
    to.col(i) = noisy.target[i];
  }
  const Eigen::Matrix4d closed_form = Eigen::umeyama(from, to, false);
  EXPECT_LT(difference(pointToPointLm(noisy.source, noisy.target).matrix(), closed_form), 1e-9);
}

TEST(PointToPointLmTest, LandsWherePclsNumericalLevenbergMarquardtDoes) {
  const Pairs noisy = pairs(motion(0.1, 0.0, {0.2, 0.05, -0.02}), 0.02, 3);
  pcl::PointCloud<pcl::PointXYZ> source, target;
  for (std::size_t i = 0; i < noisy.source.size(); ++i) {
    source.push_back(pcl::PointXYZ(noisy.source[i].x(), noisy.source[i].y(), noisy.source[i].z()));
    target.push_back(pcl::PointXYZ(noisy.target[i].x(), noisy.target[i].y(), noisy.target[i].z()));
  }
  Eigen::Matrix4f pcl_motion = Eigen::Matrix4f::Identity();
  pcl::registration::TransformationEstimationLM<pcl::PointXYZ, pcl::PointXYZ> pcl_lm;
  pcl_lm.estimateRigidTransformation(source, target, pcl_motion);
  const Eigen::Matrix4d ours = pointToPointLm(noisy.source, noisy.target).matrix();
  // PCL's float LM stops at a relative tolerance of sqrt(float epsilon), 3.5e-4.
  EXPECT_LT(difference(ours, pcl_motion.cast<double>()), 1e-3);
}

TEST(PointToPointLmTest, NoPairsLeaveTheIdentity) {
  EXPECT_TRUE(pointToPointLm({}, {}).matrix().isIdentity());
}

}  // namespace
}  // namespace granular
