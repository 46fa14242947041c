// Every PCL registration template (ICP, ICP-NL, NDT) is instantiated in this one translation
// unit: they take minutes to compile, so no other file includes their headers.
#include "granular_core/classification/registration_classifier.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <pcl/registration/icp.h>
#include <pcl/registration/icp_nl.h>
#include <pcl/registration/ndt.h>
#include <pcl/search/kdtree.h>

#include "granular_core/classification/ndt_matcher.h"
#include "granular_core/classification/nearest_grid.h"
#include "granular_core/classification/nearest_points.h"

namespace granular {
namespace {

using Point = pcl::PointXYZ;
using CloudPtr = ModelCloud::Ptr;
using CloudConstPtr = ModelCloud::ConstPtr;
using Criteria = pcl::registration::DefaultConvergenceCriteria<float>;

// The model search structure of the cached path, shared read-only by all threads. It answers
// ICP's single-neighbour queries from a NearestGrid of the model and, for the queries its
// rings cannot settle, from a NearestPoints kd-tree; and the fitness score from the kd-tree,
// four object points at a time. Every distance is the one PCL's KdTreeFLANN gives, bit for
// bit, without its cost per query: PCL allocates and enters an OpenMP parallel region (FLANN's
// knnSearch) for each point, which for these small objects costs more than the search. Two
// searches are also bounded, without changing their answers:
//  - ICP's correspondence estimation discards a nearest point beyond the maximum
//    correspondence distance, so a search needs to look no farther (setCorrespondenceBound);
//  - fitness() bounds each point's search by the previous point's distance plus the step
//    between the two points: neighbouring scan points have neighbouring nearest points.
class NearestTree : public pcl::search::KdTree<Point> {
 public:
  using Ptr = std::shared_ptr<NearestTree>;
  using pcl::search::KdTree<Point>::nearestKSearch;

  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    pcl::search::KdTree<Point>::setInputCloud(cloud, indices);
    points_.clear();
    mapping_.clear();
    const auto add = [&](pcl::index_t i) {
      const Point& point = (*cloud)[static_cast<std::size_t>(i)];
      if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
        points_.insert(points_.end(), {point.x, point.y, point.z});
        mapping_.push_back(i);
      }
    };
    if (indices) {
      for (const pcl::index_t i : *indices) {
        add(i);
      }
    } else {
      for (std::size_t i = 0; i < cloud->size(); ++i) {
        add(static_cast<pcl::index_t>(i));
      }
    }
    grid_ = std::make_unique<NearestGrid>(points_.data(), mapping_.size(), kGridRings);
    tree_ = std::make_unique<NearestPoints>(points_.data(), mapping_.size());
  }

  // Single-neighbour queries beyond `max_distance` (m) then report no neighbour (an infinite
  // distance), which PCL's correspondence estimation discards as it would the real one.
  void setCorrespondenceBound(double max_distance) {
    // The smallest float above every float distance d with d <= max_distance^2 (double), as
    // PCL compares them.
    const double limit = max_distance * max_distance;
    float bound = static_cast<float>(limit);
    if (static_cast<double>(bound) < limit) {
      bound = std::nextafter(bound, std::numeric_limits<float>::infinity());
    }
    correspondence_bound_ = std::nextafter(bound, std::numeric_limits<float>::infinity());
  }

  int nearestKSearch(const Point& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    if (k != 1 || mapping_.empty()) {
      return pcl::search::KdTree<Point>::nearestKSearch(point, k, k_indices, k_sqr_distances);
    }
    const float query[3] = {point.x, point.y, point.z};
    const NearestGrid::Result nearest = nearestWithin(query, correspondence_bound_);
    k_indices.assign(1, nearest.found ? mapping_[nearest.index] : 0);
    k_sqr_distances.assign(
        1, nearest.found ? nearest.distance : std::numeric_limits<float>::infinity());
    return 1;
  }

  // What PCL's Registration::getFitnessScore() gives for `source` aligned by `transform` on
  // this model: the mean squared distance of each transformed point to its nearest model point.
  // Most points of most pairs lie far from the model (the wrong classes), where the grid's rings
  // cannot settle them: all go to the kd-tree, kPacket neighbours in the scan at a time.
  double fitness(const ModelCloud& source, const Eigen::Matrix4f& transform) const {
    if (mapping_.empty() || source.empty()) {
      return std::numeric_limits<double>::max();
    }
    ModelCloud moved;
    pcl::transformPointCloud(source, moved, transform);
    constexpr int kPacket = NearestPoints::kPacket;
    std::vector<float> distances(moved.size());
    for (std::size_t first = 0; first < moved.size(); first += kPacket) {
      float queries[kPacket][3];
      float bounds[kPacket];
      for (int lane = 0; lane < kPacket; ++lane) {
        // The last packet is filled up with its last point again.
        const pcl::PointXYZ& point = moved[std::min(first + lane, moved.size() - 1)];
        std::copy(point.data, point.data + 3, queries[lane]);
        bounds[lane] = std::numeric_limits<float>::infinity();
        if (first > 0) {
          // No farther than the previous point's nearest model point: at most the previous
          // distance plus the step between the two points (widened for rounding).
          const pcl::PointXYZ& previous = moved[first - 1];
          const double step = std::sqrt(static_cast<double>(
              flannSquaredDistance(queries[lane], previous.data)));
          const double reach = std::sqrt(static_cast<double>(distances[first - 1])) + step;
          bounds[lane] = static_cast<float>(reach * reach * (1.0 + 1.0e-5) + 1.0e-30);
        }
      }
      float nearest[kPacket];
      tree_->nearestDistances(queries, bounds, nearest);
      std::copy(nearest, nearest + std::min<std::size_t>(kPacket, moved.size() - first),
                distances.begin() + static_cast<std::ptrdiff_t>(first));
    }
    double sum = 0.0;
    for (const float distance : distances) {
      sum += distance;
    }
    return sum / static_cast<double>(distances.size());
  }

 private:
  // Rings of grid cells a query searches before it asks the kd-tree: one settles the queries
  // on and near the model's surface, which are most of them.
  static constexpr int kGridRings = 1;

  // The nearest point closer than `bound` (squared): from the grid, or from the kd-tree when
  // the grid cannot settle it, bounded by what the grid found.
  NearestGrid::Result nearestWithin(const float query[3], float bound) const {
    NearestGrid::Result nearest = grid_->nearest(query, bound);
    if (nearest.resolved) {
      return nearest;
    }
    const NearestPoints::Result exact = tree_->nearest(
        query, nearest.found
                   ? std::nextafter(nearest.distance, std::numeric_limits<float>::infinity())
                   : bound);
    nearest.found = exact.found;
    nearest.index = exact.index;
    nearest.distance = exact.distance;
    return nearest;
  }

  std::vector<float> points_;
  pcl::Indices mapping_;
  std::unique_ptr<NearestGrid> grid_;
  std::unique_ptr<NearestPoints> tree_;
  float correspondence_bound_ = std::numeric_limits<float>::infinity();
};

// ICP and ICP-NL with the two things PCL keeps protected that a reused object needs.
template <typename Base>
class ReusableIcp : public Base {
 public:
  int iterations() const { return this->nr_iterations_; }

  // DefaultConvergenceCriteria keeps the previous run's mean squared error (and state)
  // across align() calls, so the first iteration of the next object would compare against
  // it; a fresh criteria object makes a reused ICP behave exactly like a new one.
  void resetConvergenceCriteria() {
    this->convergence_criteria_.reset(
        new Criteria(this->nr_iterations_, this->transformation_, *this->correspondences_));
  }
};
using Icp = ReusableIcp<pcl::IterativeClosestPoint<Point, Point>>;
using IcpNl = ReusableIcp<pcl::IterativeClosestPointNonLinear<Point, Point>>;

using Ndt = pcl::NormalDistributionsTransform<Point, Point>;

template <typename Registration>
void configure(Registration& icp, const IcpClassifierConfig& config) {
  icp.setMaximumIterations(config.max_iterations);
  icp.setMaxCorrespondenceDistance(config.max_correspondence_distance);
  icp.setTransformationEpsilon(config.transformation_epsilon);
  icp.setEuclideanFitnessEpsilon(config.euclidean_fitness_epsilon);
}

void configure(Ndt& ndt, const NdtClassifierConfig& config) {
  ndt.setTransformationEpsilon(config.transformation_epsilon);
  ndt.setStepSize(config.step_size);
  ndt.setMaximumIterations(config.max_iterations);
  ndt.setOulierRatio(config.outlier_ratio);  // sic, PCL 1.13
  // Before the target: both shape the voxel grid that setInputTarget builds.
  ndt.setMinPointPerVoxel(static_cast<unsigned int>(config.min_points_per_voxel));
  ndt.setResolution(static_cast<float>(config.resolution));
}

RegistrationState icpState(Criteria::ConvergenceState state) {
  switch (state) {
    case Criteria::CONVERGENCE_CRITERIA_TRANSFORM:
      return RegistrationState::kTransform;
    case Criteria::CONVERGENCE_CRITERIA_ABS_MSE:
      return RegistrationState::kAbsMse;
    case Criteria::CONVERGENCE_CRITERIA_REL_MSE:
      return RegistrationState::kRelMse;
    case Criteria::CONVERGENCE_CRITERIA_ITERATIONS:
    case Criteria::CONVERGENCE_CRITERIA_FAILURE_AFTER_MAX_ITERATIONS:
      return RegistrationState::kIterations;
    case Criteria::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES:
      return RegistrationState::kNoCorrespondences;
    case Criteria::CONVERGENCE_CRITERIA_NOT_CONVERGED:
      break;
  }
  return RegistrationState::kFailed;
}

// PCL's fitness score of the last alignment, from `tree` when given.
template <typename Registration>
double fitnessOf(Registration& registration, const NearestTree* tree) {
  return tree != nullptr ? tree->fitness(*registration.getInputSource(),
                                         registration.getFinalTransformation())
                         : registration.getFitnessScore();
}

// Aligns `source` with a registration object whose target is set; `aligned` is scratch.
// `tree`: the target's NearestTree, for the fitness; nullptr uses PCL's getFitnessScore().
template <typename Registration>
PairResult alignIcp(Registration& icp, const CloudConstPtr& source, ModelCloud& aligned,
                    const NearestTree* tree) {
  icp.setInputSource(source);
  icp.align(aligned);
  PairResult result;
  result.state = icpState(icp.getConvergeCriteria()->getConvergenceState());
  result.iterations = icp.iterations();
  result.transform = icp.getFinalTransformation();
  result.fitness = fitnessOf(icp, tree);
  return result;
}

// An NDT alignment's state from what PCL's NDT reports.
RegistrationState ndtState(double likelihood, bool converged, int iterations,
                           int max_iterations) {
  if (likelihood == 0.0) {
    return RegistrationState::kNoCorrespondences;  // no object point near any model cell
  }
  if (!converged) {
    return RegistrationState::kFailed;
  }
  return iterations >= max_iterations ? RegistrationState::kIterations
                                      : RegistrationState::kTransform;
}

// The report's NDT: PCL's, with its own fitness score.
PairResult alignNdt(Ndt& ndt, const CloudConstPtr& source, ModelCloud& aligned,
                    int max_iterations) {
  ndt.setInputSource(source);
  ndt.align(aligned);
  PairResult result;
  result.iterations = ndt.getFinalNumIteration();
  result.state = ndtState(ndt.getTransformationLikelihood(), ndt.hasConverged(),
                          result.iterations, max_iterations);
  result.transform = ndt.getFinalTransformation();
  result.fitness = ndt.getFitnessScore();
  return result;
}

// The same alignment through the model's NdtMatcher, the fitness from its NearestTree.
PairResult alignNdt(const NdtMatcher& ndt, const ModelCloud& source, int max_iterations,
                    const NearestTree& tree) {
  const NdtMatcher::Result aligned = ndt.align(source);
  PairResult result;
  result.iterations = aligned.iterations;
  result.state =
      ndtState(aligned.likelihood, aligned.converged, aligned.iterations, max_iterations);
  result.transform = aligned.transform;
  result.fitness = tree.fitness(source, aligned.transform);
  return result;
}

PairResult failedPair() {
  PairResult result;
  result.state = RegistrationState::kFailed;
  return result;
}

// The object as registered: its points at or above min_z, when set.
CloudConstPtr sourceOf(const ModelCloud& object, const std::optional<double>& min_z) {
  CloudPtr source(new ModelCloud);
  if (!min_z) {
    *source = object;
    return source;
  }
  source->reserve(object.size());
  for (const Point& point : object.points) {
    if (point.z >= *min_z) {
      source->push_back(point);
    }
  }
  return source;
}

}  // namespace

struct RegistrationClassifier::Impl {
  RegistrationMethod method;
  RegistrationClassifierConfig config;
  std::vector<std::string> labels;
  std::vector<CloudConstPtr> models;
  std::vector<NearestTree::Ptr> trees;  // built once, shared read-only by every thread
  std::vector<std::unique_ptr<const NdtMatcher>> ndt_matchers;  // cells built once, shared
  std::vector<std::string> warnings;

  const IcpClassifierConfig& icpConfig() const {
    return method == RegistrationMethod::kIcpNl ? config.icp_nl : config.icp;
  }

  // One thread's registration objects: one per model, sharing the prebuilt structures.
  class Worker {
   public:
    explicit Worker(const Impl& impl) : impl_(impl) {
      for (std::size_t m = 0; m < impl.models.size(); ++m) {
        switch (impl.method) {
          case RegistrationMethod::kIcp:
            icp_.push_back(prepared<Icp>(m));
            break;
          case RegistrationMethod::kIcpNl:
            icp_nl_.push_back(prepared<IcpNl>(m));
            break;
          case RegistrationMethod::kNdt:
            break;  // the NdtMatchers are const and shared
        }
      }
    }

    std::vector<PairResult> registerObject(const CloudConstPtr& source) {
      std::vector<PairResult> results(impl_.models.size());
      for (std::size_t m = 0; m < results.size(); ++m) {
        try {
          switch (impl_.method) {
            case RegistrationMethod::kIcp:
              icp_[m]->resetConvergenceCriteria();
              results[m] = alignIcp(*icp_[m], source, aligned_, impl_.trees[m].get());
              break;
            case RegistrationMethod::kIcpNl:
              icp_nl_[m]->resetConvergenceCriteria();
              results[m] = alignIcp(*icp_nl_[m], source, aligned_, impl_.trees[m].get());
              break;
            case RegistrationMethod::kNdt:
              results[m] = alignNdt(*impl_.ndt_matchers[m], *source,
                                    impl_.config.ndt.max_iterations, *impl_.trees[m]);
              break;
          }
        } catch (const std::exception&) {
          results[m] = failedPair();
        }
      }
      return results;
    }

   private:
    template <typename Registration>
    std::unique_ptr<Registration> prepared(std::size_t m) const {
      auto registration = std::make_unique<Registration>();
      configure(*registration, impl_.icpConfig());
      registration->setInputTarget(impl_.models[m]);
      // true: never rebuild the tree (it is shared, and already built on this target).
      registration->setSearchMethodTarget(impl_.trees[m], true);
      return registration;
    }

    const Impl& impl_;
    std::vector<std::unique_ptr<Icp>> icp_;
    std::vector<std::unique_ptr<IcpNl>> icp_nl_;
    ModelCloud aligned_;
  };

  // The report's loop for one pair: a new registration object, given the model as target.
  PairResult registerPlain(const CloudConstPtr& source, std::size_t m) const {
    ModelCloud aligned;
    try {
      switch (method) {
        case RegistrationMethod::kIcp: {
          Icp icp;
          configure(icp, config.icp);
          icp.setInputTarget(models[m]);
          return alignIcp(icp, source, aligned, nullptr);
        }
        case RegistrationMethod::kIcpNl: {
          IcpNl icp;
          configure(icp, config.icp_nl);
          icp.setInputTarget(models[m]);
          return alignIcp(icp, source, aligned, nullptr);
        }
        case RegistrationMethod::kNdt: {
          Ndt ndt;
          configure(ndt, config.ndt);
          ndt.setInputTarget(models[m]);
          return alignNdt(ndt, source, aligned, config.ndt.max_iterations);
        }
      }
    } catch (const std::exception&) {
    }
    return failedPair();
  }

  bool tooSmall(const ModelCloud& source) const {
    return source.size() < minimumSourcePoints(method);
  }
};

RegistrationClassifier::RegistrationClassifier(RegistrationMethod method,
                                               const RegistrationClassifierConfig& config,
                                               std::vector<LabelledModel> models)
    : impl_(std::make_unique<Impl>()) {
  validate(config);
  if (models.empty()) {
    throw std::invalid_argument("no class models");
  }
  impl_->method = method;
  impl_->config = config;
  for (LabelledModel& model : models) {
    if (model.label.empty()) {
      throw std::invalid_argument("a class model has an empty label");
    }
    if (std::find(impl_->labels.begin(), impl_->labels.end(), model.label) !=
        impl_->labels.end()) {
      throw std::invalid_argument("two class models are labelled '" + model.label + "'");
    }
    if (model.cloud.empty()) {
      throw std::invalid_argument("the model of class '" + model.label + "' has no points");
    }
    impl_->labels.push_back(model.label);
    const CloudConstPtr cloud(new ModelCloud(std::move(model.cloud)));
    impl_->models.push_back(cloud);

    NearestTree::Ptr tree(new NearestTree);
    if (method != RegistrationMethod::kNdt) {
      tree->setCorrespondenceBound(impl_->icpConfig().max_correspondence_distance);
    }
    tree->setInputCloud(cloud);
    impl_->trees.push_back(tree);

    if (method == RegistrationMethod::kNdt) {
      auto ndt = std::make_unique<const NdtMatcher>(*cloud, config.ndt);
      if (ndt->cells() == 0) {
        // PCL's NDT then returns at once without aligning; the pairs record that as
        // no_correspondences, with the fitness of the object where it is.
        impl_->warnings.push_back(
            "NDT: no voxel of " + std::to_string(config.ndt.resolution) + " m holds " +
            std::to_string(config.ndt.min_points_per_voxel) + " of the " +
            std::to_string(cloud->size()) + " points of the model of class '" + model.label +
            "', so it has no cell to match and no object is aligned to it "
            "(no_correspondences); a coarser ndt.resolution gives it cells");
      }
      impl_->ndt_matchers.push_back(std::move(ndt));
    }
  }
}

RegistrationClassifier::~RegistrationClassifier() = default;
RegistrationClassifier::RegistrationClassifier(RegistrationClassifier&&) noexcept = default;
RegistrationClassifier& RegistrationClassifier::operator=(RegistrationClassifier&&) noexcept =
    default;

RegistrationMethod RegistrationClassifier::method() const { return impl_->method; }

const RegistrationClassifierConfig& RegistrationClassifier::config() const {
  return impl_->config;
}

std::vector<std::string> RegistrationClassifier::labels() const { return impl_->labels; }

const std::vector<std::string>& RegistrationClassifier::warnings() const {
  return impl_->warnings;
}

int registrationThreads(const RegisterOptions& options) {
  if (options.threads > 0) {
    return options.threads;
  }
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

std::vector<std::vector<PairResult>> RegistrationClassifier::registerObjects(
    const std::vector<ModelCloud>& objects, const RegisterOptions& options) const {
  const Impl& impl = *impl_;
  std::vector<std::vector<PairResult>> results(objects.size());
  const long count = static_cast<long>(objects.size());
  std::size_t done = 0;
  std::exception_ptr error;
#pragma omp parallel num_threads(registrationThreads(options))
  {
    // Each thread's own registration objects; building them costs no tree or voxel grid.
    std::unique_ptr<Impl::Worker> worker;
    try {
      worker = std::make_unique<Impl::Worker>(impl);
    } catch (...) {
#pragma omp critical(granular_registration_error)
      error = error ? error : std::current_exception();
    }
    // Objects differ a hundredfold in size: small dynamic chunks keep the threads even.
#pragma omp for schedule(dynamic, 4)
    for (long i = 0; i < count; ++i) {
      if (!worker) {
        continue;
      }
      const CloudConstPtr source = sourceOf(objects[static_cast<std::size_t>(i)],
                                            impl.config.source_min_z);
      std::vector<PairResult>& result = results[static_cast<std::size_t>(i)];
      if (impl.tooSmall(*source)) {
        result.assign(impl.models.size(), PairResult());
      } else {
        result = worker->registerObject(source);
      }
#pragma omp critical(granular_registration_progress)
      {
        ++done;
        if (options.progress) {
          options.progress(done, objects.size());
        }
      }
    }
  }
  if (error) {
    std::rethrow_exception(error);
  }
  return results;
}

std::vector<std::vector<PairResult>> RegistrationClassifier::registerObjectsPlain(
    const std::vector<ModelCloud>& objects,
    const std::function<void(std::size_t, std::size_t)>& progress) const {
  std::vector<std::vector<PairResult>> results(objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const CloudConstPtr source = sourceOf(objects[i], impl_->config.source_min_z);
    results[i].resize(impl_->models.size());
    if (!impl_->tooSmall(*source)) {
      for (std::size_t m = 0; m < impl_->models.size(); ++m) {
        results[i][m] = impl_->registerPlain(source, m);
      }
    }
    if (progress) {
      progress(i + 1, objects.size());
    }
  }
  return results;
}

}  // namespace granular
