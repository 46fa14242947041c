#include "granular_core/registration/reference.h"

#include <cmath>
#include <exception>

#include <pcl/registration/icp.h>
#include <pcl/registration/icp_nl.h>
#include <pcl/registration/ndt.h>

#include "granular_core/registration/criteria.h"
#include "icp_common.h"
#include "ndt_common.h"

namespace granular {
namespace {

using Point = pcl::PointXYZ;
using Icp = icp_detail::IcpWithIterations<pcl::IterativeClosestPoint<Point, Point>>;
using IcpNl = icp_detail::IcpWithIterations<pcl::IterativeClosestPointNonLinear<Point, Point>>;
using Ndt = pcl::NormalDistributionsTransform<Point, Point>;

template <typename Registration>
PairResult icpPair(const IcpClassifierConfig& config, const ModelCloud::ConstPtr& source,
                   const ModelCloud::ConstPtr& model) {
  ModelCloud aligned;
  // The coarse stage: a registration of its own, whose transform the second starts from.
  Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();
  int coarse_iterations = 0;
  if (config.coarse_iterations > 0) {
    IcpClassifierConfig coarse_config = config;
    coarse_config.max_iterations = config.coarse_iterations;
    coarse_config.max_correspondence_distance = config.coarse_correspondence_distance;
    Registration coarse;
    icp_detail::configure(coarse, coarse_config);
    coarse.setInputTarget(model);
    coarse.setInputSource(source);
    coarse.align(aligned);
    guess = coarse.getFinalTransformation();
    coarse_iterations = coarse.iterations();
  }
  Registration icp;
  icp_detail::configure(icp, config);
  icp.setInputTarget(model);
  PairResult result = icp_detail::alignIcp(icp, source, aligned, guess);
  result.iterations += coarse_iterations;
  return result;
}

PairResult ndtPair(const NdtClassifierConfig& config, const ModelCloud::ConstPtr& source,
                   const ModelCloud::ConstPtr& model) {
  Ndt ndt;
  ndt.setTransformationEpsilon(config.transformation_epsilon);
  ndt.setStepSize(config.step_size);
  ndt.setMaximumIterations(config.max_iterations);
  ndt.setOulierRatio(config.outlier_ratio);  // sic, PCL 1.13
  // Before the target: both shape the voxel grid that setInputTarget builds.
  ndt.setMinPointPerVoxel(static_cast<unsigned int>(config.min_points_per_voxel));
  ndt.setResolution(static_cast<float>(config.resolution));
  ndt.setInputTarget(model);
  ndt.setInputSource(source);
  ModelCloud aligned;
  ndt.align(aligned);
  PairResult result;
  result.iterations = ndt.getFinalNumIteration();
  result.state = ndt_detail::ndtState(ndt.getTransformationLikelihood(), ndt.hasConverged(),
                                      result.iterations, config.max_iterations);
  result.transform = ndt.getFinalTransformation();
  result.fitness = ndt.getFitnessScore();
  return result;
}

PairResult registerPair(RegistrationMethod method, const RegistrationClassifierConfig& config,
                        const ModelCloud::ConstPtr& source, const ModelCloud::ConstPtr& model) {
  try {
    switch (method) {
      case RegistrationMethod::kIcp:
        return icpPair<Icp>(config.icp, source, model);
      case RegistrationMethod::kIcpNl:
        return icpPair<IcpNl>(config.icp_nl, source, model);
      case RegistrationMethod::kNdt:
        return ndtPair(config.ndt, source, model);
    }
  } catch (const std::exception&) {
  }
  return failedPair();
}

}  // namespace

std::vector<std::vector<PairResult>> registerObjectsReference(
    RegistrationMethod method, const RegistrationClassifierConfig& config,
    const std::vector<LabelledModel>& models, const std::vector<ModelCloud>& objects,
    const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<ModelCloud::ConstPtr> clouds;
  for (const LabelledModel& model : models) {
    clouds.emplace_back(new ModelCloud(model.cloud));
  }
  std::vector<std::vector<PairResult>> results(objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ModelCloud::ConstPtr source = registrationSource(objects[i], config);
    results[i].resize(clouds.size());
    if (source->size() >= minimumSourcePoints(method)) {
      for (std::size_t m = 0; m < clouds.size(); ++m) {
        results[i][m] = registerPair(method, config, source, clouds[m]);
      }
    }
    if (progress) {
      progress(i + 1, objects.size());
    }
  }
  return results;
}

ReferenceComparison compareWithReference(const std::vector<std::vector<PairResult>>& reference,
                                         const std::vector<std::vector<PairResult>>& ours) {
  ReferenceComparison comparison;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const Predictions expected = predict(reference[i]);
    const Predictions got = predict(ours[i]);
    for (int criterion = 1; criterion <= 3; ++criterion) {
      if (expected.criterion(criterion) != got.criterion(criterion)) {
        ++comparison.different_predictions;
        break;
      }
    }
    for (std::size_t m = 0; m < reference[i].size(); ++m) {
      const PairResult& a = reference[i][m];
      const PairResult& b = ours[i][m];
      comparison.rejected_pairs += b.rejected;
      const bool same_fitness =
          b.rejected || a.fitness == b.fitness || (std::isnan(a.fitness) && std::isnan(b.fitness));
      if (a.state != b.state || a.iterations != b.iterations || !same_fitness ||
          a.transform != b.transform) {
        ++comparison.different_pairs;
      }
    }
  }
  return comparison;
}

double criterion2Accuracy(const std::vector<std::vector<PairResult>>& results,
                          const std::vector<std::string>& labels,
                          const std::vector<LabelledModel>& models) {
  std::size_t correct = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::optional<std::size_t> predicted = predict(results[i]).criterion2;
    correct += predicted && models[*predicted].label == labels[i];
  }
  return results.empty() ? 0.0 : static_cast<double>(correct) / results.size();
}

}  // namespace granular
