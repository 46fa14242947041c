#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/registration/criteria.h"
#include "granular_core/registration/registration_classifier.h"
#include "granular_core/search/nearest_tree.h"
#include "levelled_object.h"

namespace granular {
namespace {

// One class model: its box in its own frame, its search tree for the fitness before
// registration, and a classifier holding it alone, to register against it.
struct ModelEntry {
  std::string label;
  Eigen::Vector2d low, high;  ///< x, y extent of the cloud
  double top = 0.0;           ///< m, its highest point (its box stands on z = 0)
  NearestTree::Ptr tree;
  std::unique_ptr<RegistrationClassifier> classifier;
};

// A placement of a model on the object: the model frame in the levelled frame.
struct Hypothesis {
  std::size_t model = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< model frame -> levelled
  ModelCloud::Ptr source;  ///< the object's thinned points in the model frame
  double fitness = std::numeric_limits<double>::infinity();
};

// The points thinned to the first of each `voxel` (m) cube, in the order of their cubes.
std::vector<Eigen::Vector3d> thinned(const std::vector<Eigen::Vector3d>& points, double voxel) {
  std::vector<std::pair<std::uint64_t, std::size_t>> keys;
  keys.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t key = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const auto cell = static_cast<std::int64_t>(std::floor(points[i][axis] / voxel));
      key = (key << 21) | (static_cast<std::uint64_t>(cell) & 0x1fffffULL);
    }
    keys.emplace_back(key, i);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<Eigen::Vector3d> kept;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i == 0 || keys[i].first != keys[i - 1].first) {
      kept.push_back(points[keys[i].second]);
    }
  }
  return kept;
}

}  // namespace

struct ModelCuboidFitter::Impl {
  CuboidConfig config;
  std::vector<ModelEntry> models;
};

ModelCuboidFitter::ModelCuboidFitter(const CuboidConfig& config, std::vector<LabelledModel> models)
    : impl_(std::make_unique<Impl>()) {
  validate(config);
  if (models.empty()) {
    throw std::invalid_argument("model-based cuboid fitting needs class models");
  }
  impl_->config = config;
  std::sort(models.begin(), models.end(),
            [](const LabelledModel& a, const LabelledModel& b) { return a.label < b.label; });
  for (LabelledModel& model : models) {
    if (model.cloud.empty()) {
      throw std::invalid_argument("the model of class '" + model.label + "' has no points");
    }
    ModelEntry entry;
    entry.label = model.label;
    entry.low.setConstant(std::numeric_limits<double>::infinity());
    entry.high.setConstant(-std::numeric_limits<double>::infinity());
    for (const pcl::PointXYZ& point : model.cloud) {
      const Eigen::Vector2d xy(point.x, point.y);
      entry.low = entry.low.cwiseMin(xy);
      entry.high = entry.high.cwiseMax(xy);
      entry.top = std::max(entry.top, double(point.z));
    }
    const ModelCloud::ConstPtr cloud(new ModelCloud(model.cloud));
    entry.tree = std::make_shared<NearestTree>();
    entry.tree->setInputCloud(cloud);
    std::vector<LabelledModel> alone;
    alone.push_back(std::move(model));
    entry.classifier = std::make_unique<RegistrationClassifier>(
        config.model.method, config.model.registration, std::move(alone));
    impl_->models.push_back(std::move(entry));
  }
}

ModelCuboidFitter::~ModelCuboidFitter() = default;

std::vector<std::string> ModelCuboidFitter::labels() const {
  std::vector<std::string> labels;
  for (const ModelEntry& model : impl_->models) {
    labels.push_back(model.label);
  }
  return labels;
}

std::optional<FittedCuboid> ModelCuboidFitter::fit(const ObjectView& object) const {
  const CuboidConfig& config = impl_->config;
  const std::optional<cuboids::LevelledObject> levelled =
      cuboids::levelObject(object, config.points);
  if (!levelled) {
    return std::nullopt;
  }
  const std::vector<Eigen::Vector3d> points = thinned(levelled->points, config.model.voxel);
  const AxisRectangle rectangle = cuboids::lshapeRectangle(*levelled, config.lshape);
  const Eigen::Vector2d body = cuboids::bodyExtent(*levelled, rectangle);
  std::optional<double> shortfall;  // the same for every model: computed once, if asked
  const auto across_shortfall = [&] {
    if (!shortfall) {
      shortfall = cuboids::acrossShortfall(*levelled);
    }
    return *shortfall;
  };

  // Every placement, measured where it was placed.
  std::vector<Hypothesis> hypotheses;
  for (std::size_t m = 0; m < impl_->models.size(); ++m) {
    const ModelEntry& model = impl_->models[m];
    const Eigen::Vector2d size = model.high - model.low;
    const Eigen::Vector2d middle = (model.low + model.high) / 2;
    // With two headings, the length axis the geometric fit would take with this model's size.
    const int geometric_axis =
        cuboids::lengthAxis(body, size.y(), config.geometric.width_tolerance,
                            rectangle.coordinates(rectangle.centre() - levelled->sensor),
                            across_shortfall);
    for (int axis = 0; axis < 2; ++axis) {
      if (config.model.headings == 2 && axis != geometric_axis) {
        continue;
      }
      const AxisRectangle grown = cuboids::grownFromSeenCorner(rectangle, levelled->sensor, axis,
                                                               size.x(), size.y());
      for (const double flip : {0.0, M_PI}) {
        Hypothesis hypothesis;
        hypothesis.model = m;
        const double yaw = grown.heading + (axis == 1 ? M_PI / 2 : 0.0) + flip;
        const Eigen::Matrix3d turn =
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        hypothesis.pose.linear() = turn;
        const Eigen::Vector3d origin =
            Eigen::Vector3d(grown.centre().x(), grown.centre().y(), 0.0) -
            turn * Eigen::Vector3d(middle.x(), middle.y(), 0.0);
        hypothesis.pose.translation() = origin;
        const Eigen::Isometry3d to_model = hypothesis.pose.inverse();
        hypothesis.source.reset(new ModelCloud);
        hypothesis.source->reserve(points.size());
        for (const Eigen::Vector3d& point : points) {
          const Eigen::Vector3f q = (to_model * point).cast<float>();
          hypothesis.source->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
        }
        hypothesis.fitness = model.tree->fitness(
            *registrationSource(*hypothesis.source, config.model.registration),
            Eigen::Matrix4f::Identity());
        hypotheses.push_back(std::move(hypothesis));
      }
    }
  }
  const std::size_t registered =
      std::min(hypotheses.size(), static_cast<std::size_t>(config.model.registered));
  std::partial_sort(hypotheses.begin(), hypotheses.begin() + static_cast<std::ptrdiff_t>(registered),
                    hypotheses.end(), [](const Hypothesis& a, const Hypothesis& b) {
                      return a.fitness < b.fitness;
                    });
  hypotheses.resize(registered);

  // The best registered placement by the report's criteria; the best placement as measured
  // before registration when none could be registered.
  RegisterOptions one_thread;
  one_thread.threads = 1;
  std::vector<PairResult> results;
  for (const Hypothesis& hypothesis : hypotheses) {
    const RegistrationClassifier& classifier = *impl_->models[hypothesis.model].classifier;
    results.push_back(classifier.registerObjects({*hypothesis.source}, one_thread)[0][0]);
  }
  const Predictions predictions = predict(results);
  const std::optional<std::size_t> chosen =
      predictions.criterion2 ? predictions.criterion2 : predictions.criterion3;
  const std::size_t best = chosen ? *chosen : 0;
  const ModelEntry& model = impl_->models[hypotheses[best].model];
  Eigen::Isometry3d registration = Eigen::Isometry3d::Identity();
  double fitness = hypotheses[best].fitness;
  if (chosen) {
    registration.matrix() = results[best].transform.cast<double>();
    fitness = results[best].fitness;
  }
  // The model's box in the levelled frame: the hypothesis's pose, undone by the registration
  // (which maps the object's points onto the model).
  const Eigen::Isometry3d model_pose = hypotheses[best].pose * registration.inverse();
  const Eigen::Vector2d middle = (model.low + model.high) / 2;
  const Eigen::Vector3d centre = model_pose * Eigen::Vector3d(middle.x(), middle.y(), 0.0);
  const Eigen::Vector3d forward = model_pose.linear() * Eigen::Vector3d::UnitX();
  const Eigen::Vector2d size = model.high - model.low;
  FittedCuboid cuboid{
      model.label, std::exp(-fitness / config.model.score_scale),
      cuboids::sensorBox(levelled->levelling, centre.head<2>(),
                         std::atan2(forward.y(), forward.x()),
                         Eigen::Vector3d(size.x(), size.y(), model.top)),
      levelled->points.size()};
  return cuboid;
}


}  // namespace granular
