// A class model and a copy of it moved by a known rigid motion, for the registration methods'
// own tests: each must undo the motion.
#pragma once

#include <cmath>
#include <memory>
#include <random>

#include <Eigen/Geometry>
#include <pcl/common/transforms.h>

#include "granular_core/registration/registration.h"
#include "support/model_clouds.h"

namespace granular {
namespace testing_support {

// A car-sized box surface, and the motion the source copy is moved by: 3 degrees about z and
// (5, -4, 2) cm, within reach of a 0.2 m pairing bound.
struct KnownMotion {
  ModelCloud::ConstPtr model;
  Eigen::Matrix4f motion = Eigen::Matrix4f::Identity();
  ModelCloud::ConstPtr source;

  explicit KnownMotion(const Eigen::Vector3f& shift = Eigen::Vector3f(0.05f, -0.04f, 0.02f)) {
    std::mt19937 random(17);
    model.reset(new ModelCloud(testing_clouds::boxSurface({4.6, 1.8, 1.4}, 3000, random)));
    const Eigen::Affine3f moved = Eigen::Translation3f(shift) *
                                  Eigen::AngleAxisf(3.0f * float(M_PI) / 180.0f,
                                                    Eigen::Vector3f::UnitZ());
    motion = moved.matrix();
    ModelCloud::Ptr copy(new ModelCloud);
    pcl::transformPointCloud(*model, *copy, moved);
    source = copy;
  }

  // The model prepared as RegistrationClassifier prepares it for ICP: a tree bounded by the
  // pairing distance.
  PreparedModels prepared(double max_correspondence_distance) const {
    PreparedModels models;
    models.clouds.push_back(model);
    NearestTree::Ptr tree(new NearestTree);
    tree->setCorrespondenceBound(max_correspondence_distance);
    tree->setInputCloud(model);
    models.trees.push_back(tree);
    return models;
  }

  // The source registered to the model by the method `prepare` sets up (prepareIcp,
  // prepareIcpNl) with `config`.
  template <class Prepare>
  PairResult aligned(Prepare prepare, const IcpClassifierConfig& config) const {
    const PreparedModels models = prepared(config.max_correspondence_distance);
    return prepare(config, models)->aligner()->align(source, 0);
  }

  // How far `transform` (source to model) is from undoing the motion: metres moved at the
  // model's corners, the largest.
  double residual(const Eigen::Matrix4f& transform) const {
    const Eigen::Matrix4f error = transform * motion;
    double worst = 0.0;
    for (const float x : {-2.3f, 2.3f}) {
      for (const float y : {-0.9f, 0.9f}) {
        for (const float z : {0.0f, 1.4f}) {
          const Eigen::Vector4f corner(x, y, z, 1.0f);
          worst = std::max(worst, double((error * corner - corner).norm()));
        }
      }
    }
    return worst;
  }
};

// Configured to run to convergence: enough iterations, pairs up to 0.2 m.
inline IcpClassifierConfig convergingIcp() {
  IcpClassifierConfig config;
  config.max_iterations = 100;
  config.max_correspondence_distance = 0.2;
  config.euclidean_fitness_epsilon = 1e-6;
  return config;
}

}  // namespace testing_support
}  // namespace granular
