// NdtMatcher: PCL 1.13's NormalDistributionsTransform against one fixed model, bit for bit.
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/registration/ndt.h>

#include "granular_core/registration/ndt_matcher.h"
#include "support/model_clouds.h"

namespace granular {
namespace {

using testing_clouds::boxSurface;
using testing_clouds::shifted;

struct PclNdt {
  bool converged;
  int iterations;
  double likelihood;
  Eigen::Matrix4f transform;
};

PclNdt pclNdt(const ModelCloud& model, const ModelCloud& source,
              const NdtClassifierConfig& config) {
  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
  ndt.setTransformationEpsilon(config.transformation_epsilon);
  ndt.setStepSize(config.step_size);
  ndt.setMaximumIterations(config.max_iterations);
  ndt.setOulierRatio(config.outlier_ratio);  // sic, PCL 1.13
  ndt.setMinPointPerVoxel(static_cast<unsigned int>(config.min_points_per_voxel));
  ndt.setResolution(static_cast<float>(config.resolution));
  ndt.setInputTarget(ModelCloud::ConstPtr(new ModelCloud(model)));
  ndt.setInputSource(ModelCloud::ConstPtr(new ModelCloud(source)));
  ModelCloud aligned;
  ndt.align(aligned);
  return {ndt.hasConverged(), ndt.getFinalNumIteration(), ndt.getTransformationLikelihood(),
          ndt.getFinalTransformation()};
}

TEST(NdtMatcherTest, AlignsExactlyAsPclsNdtDoes) {
  std::mt19937 random(11);
  const ModelCloud model = boxSurface({4.4, 1.8, 1.5}, 3000, random);
  NdtClassifierConfig config;
  config.resolution = 0.3;
  config.min_points_per_voxel = 3;
  config.max_iterations = 35;
  config.transformation_epsilon = 1e-8;  // m^2: iterate until the steps are tiny
  const NdtMatcher matcher(model, config);
  ASSERT_GT(matcher.cells(), 0u);
  int moved = 0;
  for (int i = 0; i < 8; ++i) {
    // Views up to 16 cm and a few degrees off.
    const Eigen::Affine3f offset(Eigen::Translation3f(0.08f * (i % 3), -0.05f * (i % 2), 0.0f) *
                                 Eigen::AngleAxisf(0.02f * (i - 4), Eigen::Vector3f::UnitZ()));
    ModelCloud view;
    for (const pcl::PointXYZ& p : model.points) {
      if ((p.y > 0.3f || p.x > 1.0f) && view.size() < 400) {
        view.push_back(p);
      }
    }
    ModelCloud source;
    pcl::transformPointCloud(view, source, offset.matrix());
    const NdtMatcher::Result ours = matcher.align(source);
    const PclNdt pcl = pclNdt(model, source, config);
    SCOPED_TRACE("view " + std::to_string(i));
    EXPECT_EQ(ours.converged, pcl.converged);
    EXPECT_EQ(ours.iterations, pcl.iterations);
    EXPECT_EQ(ours.likelihood, pcl.likelihood);
    EXPECT_TRUE(ours.transform == pcl.transform) << ours.transform << "\nvs\n" << pcl.transform;
    moved += ours.iterations > 1;
  }
  EXPECT_GT(moved, 4) << "the views must make NDT iterate, or the comparison says little";
}

TEST(NdtMatcherTest, AModelWithoutCellsAlignsNothing) {
  ModelCloud sparse;
  for (int i = 0; i < 10; ++i) {
    sparse.push_back(pcl::PointXYZ(static_cast<float>(i), 0.0f, 0.0f));  // one point a voxel
  }
  NdtClassifierConfig config;
  config.resolution = 0.1;
  const NdtMatcher matcher(sparse, config);
  EXPECT_EQ(matcher.cells(), 0u);
  const NdtMatcher::Result result = matcher.align(sparse);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_TRUE(result.transform.isIdentity());
}

}  // namespace
}  // namespace granular
