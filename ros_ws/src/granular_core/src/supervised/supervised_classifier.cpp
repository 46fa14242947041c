// kNN and the nu-SVMs share one Impl (feature scaling, labels, the OpenCV model), one training
// path (the grid search) and one file format: kept together, over 400 lines, so that none of
// it has to be exposed in a header.
#include "granular_core/supervised/supervised_classifier.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "granular_core/dataset/atomic_file.h"
#include "granular_core/parallel.h"
#include "granular_core/search/inlier_shares.h"
#include "granular_core/supervised/knn_predictor.h"
#include "granular_core/supervised/rbf_svm.h"

namespace granular {
namespace {

constexpr const char* kFormat = "granular_supervised_classifier";
constexpr int kVersion = 1;

cv::Mat toMat(const std::vector<std::vector<float>>& rows, std::size_t columns) {
  cv::Mat mat(static_cast<int>(rows.size()), static_cast<int>(columns), CV_32F);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != columns) {
      throw std::invalid_argument("feature vector " + std::to_string(r) + " has " +
                                  std::to_string(rows[r].size()) + " values, expected " +
                                  std::to_string(columns));
    }
    std::copy(rows[r].begin(), rows[r].end(), mat.ptr<float>(static_cast<int>(r)));
  }
  return mat;
}

cv::Ptr<cv::ml::SVM> makeSvm(double nu, double gamma) {
  cv::Ptr<cv::ml::SVM> svm = cv::ml::SVM::create();
  svm->setType(cv::ml::SVM::NU_SVC);
  svm->setKernel(cv::ml::SVM::RBF);
  svm->setNu(nu);
  svm->setGamma(gamma);
  svm->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS,
                                        100000, 1e-6));
  return svm;
}

// Accuracy of a nu-SVM with (nu, gamma) across the folds; 0 where nu is infeasible for a fold.
double crossValidate(const cv::Mat& samples, const cv::Mat& responses,
                     const std::vector<int>& fold, std::size_t folds, double nu, double gamma) {
  std::size_t correct = 0;
  for (std::size_t f = 0; f < folds; ++f) {
    cv::Mat train_samples, train_responses, test_samples, test_responses;
    for (int r = 0; r < samples.rows; ++r) {
      if (fold[static_cast<std::size_t>(r)] == static_cast<int>(f)) {
        test_samples.push_back(samples.row(r));
        test_responses.push_back(responses.row(r));
      } else {
        train_samples.push_back(samples.row(r));
        train_responses.push_back(responses.row(r));
      }
    }
    if (test_samples.empty() || train_samples.empty()) {
      continue;
    }
    try {
      cv::Ptr<cv::ml::SVM> svm = makeSvm(nu, gamma);
      // An infeasible nu makes train() return false, and predicting with that model crashes.
      if (!svm->train(train_samples, cv::ml::ROW_SAMPLE, train_responses) || !svm->isTrained()) {
        continue;
      }
      // OpenCV numbers the classes the fold trained on in order: they are the class indices
      // when every class is in the fold, and RbfSvmPredictor then answers as predict() does.
      std::vector<int> present(train_responses.begin<int>(), train_responses.end<int>());
      std::sort(present.begin(), present.end());
      present.erase(std::unique(present.begin(), present.end()), present.end());
      const std::optional<RbfSvmPredictor> fast =
          present.back() + 1 == static_cast<int>(present.size())
              ? RbfSvmPredictor::from(*svm, static_cast<int>(present.size()))
              : std::nullopt;
      std::vector<int> predicted(static_cast<std::size_t>(test_samples.rows));
      if (fast) {
        const std::vector<RbfSvmPredictor::Answer> answers = fast->predict(test_samples);
        for (std::size_t r = 0; r < answers.size(); ++r) {
          predicted[r] = answers[r].label;
        }
      } else {
        cv::Mat answers;
        svm->predict(test_samples, answers);
        for (int r = 0; r < test_samples.rows; ++r) {
          predicted[static_cast<std::size_t>(r)] =
              static_cast<int>(std::lround(answers.at<float>(r)));
        }
      }
      for (int r = 0; r < test_samples.rows; ++r) {
        correct += predicted[static_cast<std::size_t>(r)] == test_responses.at<int>(r);
      }
    } catch (const cv::Exception&) {
      // An infeasible nu for this split: counts as no correct prediction.
    }
  }
  return static_cast<double>(correct) / samples.rows;
}

// Why no nu of the grid trains: the smallest class against the largest. A nu-SVM of two
// classes of n1 and n2 objects needs nu <= 2 min(n1, n2) / (n1 + n2) (Chang and Lin 2001), and
// the cross-validation folds see fewer still.
std::string infeasibleNuMessage(const std::vector<std::string>& labels, const cv::Mat& responses,
                                const std::vector<double>& nus) {
  std::vector<std::size_t> counts(labels.size(), 0);
  for (int r = 0; r < responses.rows; ++r) {
    ++counts[static_cast<std::size_t>(responses.at<int>(r))];
  }
  const auto smallest = std::min_element(counts.begin(), counts.end()) - counts.begin();
  const auto largest = std::max_element(counts.begin(), counts.end()) - counts.begin();
  const std::size_t few = counts[static_cast<std::size_t>(smallest)];
  const std::size_t many = counts[static_cast<std::size_t>(largest)];
  char bound[64];
  std::snprintf(bound, sizeof(bound), "%.3g", 2.0 * few / static_cast<double>(few + many));
  char lowest[64];
  std::snprintf(lowest, sizeof(lowest), "%.3g", *std::min_element(nus.begin(), nus.end()));
  return "no (nu, gamma) of the grid trains a nu-SVM on these objects: class '" +
         labels[static_cast<std::size_t>(smallest)] + "' has " + std::to_string(few) +
         " object(s) against " + std::to_string(many) + " of '" +
         labels[static_cast<std::size_t>(largest)] + "', which needs nu below " + bound +
         " (svm.nu's smallest is " + lowest +
         ") and more objects than the cross-validation folds; give the class more objects, "
         "lower svm.nu, or leave the class out (--classes)";
}

// The rows of each label (0, 1, ...), each list shuffled by one generator seeded `seed`.
std::vector<std::vector<int>> shuffledRowsByLabel(const cv::Mat& responses, std::uint32_t seed) {
  std::mt19937 random(seed);
  int labels = 0;
  for (int r = 0; r < responses.rows; ++r) {
    labels = std::max(labels, responses.at<int>(r) + 1);
  }
  std::vector<std::vector<int>> by_label(static_cast<std::size_t>(labels));
  for (int label = 0; label < labels; ++label) {
    std::vector<int>& members = by_label[static_cast<std::size_t>(label)];
    for (int r = 0; r < responses.rows; ++r) {
      if (responses.at<int>(r) == label) {
        members.push_back(r);
      }
    }
    std::shuffle(members.begin(), members.end(), random);
  }
  return by_label;
}

// Stratified fold of every sample: each label's samples shuffled and dealt round-robin.
std::vector<int> stratifiedFolds(const cv::Mat& responses, std::size_t folds, std::uint32_t seed) {
  std::vector<int> fold(static_cast<std::size_t>(responses.rows));
  for (const std::vector<int>& members : shuffledRowsByLabel(responses, seed)) {
    for (std::size_t k = 0; k < members.size(); ++k) {
      fold[static_cast<std::size_t>(members[k])] = static_cast<int>(k % folds);
    }
  }
  return fold;
}

// Rows of a stratified random sample of about `count` of the samples: each label's samples
// shuffled, and the first share of them in proportion kept (at least `per_label_floor`, or all
// of a smaller label), in their original order.
std::vector<int> stratifiedSample(const cv::Mat& responses, std::size_t count,
                                  std::size_t per_label_floor, std::uint32_t seed) {
  std::vector<int> rows;
  const double share = static_cast<double>(count) / responses.rows;
  for (const std::vector<int>& members : shuffledRowsByLabel(responses, seed)) {
    const std::size_t keep = std::min(
        members.size(),
        std::max(per_label_floor,
                 static_cast<std::size_t>(std::lround(share * static_cast<double>(members.size())))));
    rows.insert(rows.end(), members.begin(), members.begin() + static_cast<std::ptrdiff_t>(keep));
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

void writeHistogramConfig(cv::FileStorage& storage, const PointHistogramConfig& h) {
  storage << "histograms" << "{"
          << "sample_points" << static_cast<int>(h.sample_points)
          << "neighbours" << static_cast<int>(h.neighbours)
          << "neighbour_radius" << h.neighbour_radius << "bins" << static_cast<int>(h.bins)
          << "cylinder_height" << h.cylinder_height << "cylinder_radius" << h.cylinder_radius
          << "cylinder_slices" << static_cast<int>(h.cylinder_slices)
          << "scatter" << scatterDefinitionName(h.scatter) << "seed" << static_cast<int>(h.seed)
          << "}";
}

}  // namespace

FeatureKind featureKindOf(SupervisedMethod method) {
  switch (method) {
    case SupervisedMethod::kKnn:
      return FeatureKind::kMeanStd;
    case SupervisedMethod::kSvm:
      return FeatureKind::kPointHistograms;
    case SupervisedMethod::kSvmEsf:
      return FeatureKind::kEsf;
    case SupervisedMethod::kSvmFitness:
      return FeatureKind::kRegistrationFitness;
  }
  return FeatureKind::kMeanStd;
}

void validate(const SupervisedConfig& config) {
  config::validateFields(config);
  config::require(config.svm.log2_gamma_min <= config.svm.log2_gamma_max,
                  "svm.log2_gamma_min must be at most svm.log2_gamma_max");
}

std::string featureConfigDifference(SupervisedMethod method, const PointHistogramConfig& a,
                                    const PointHistogramConfig& b) {
  if (featureKindOf(method) != FeatureKind::kPointHistograms) {
    return "";
  }
  const config::Json first = config::toJson(a);
  const config::Json second = config::toJson(b);
  for (const auto& [key, value] : first.items()) {
    if (value != second.at(key)) {
      const auto text = [](const config::Json& json) {
        return json.is_string() ? json.get<std::string>() : json.dump();
      };
      return key + ": " + text(value) + " vs " + text(second.at(key));
    }
  }
  return "";
}

namespace {

// Whether svm_fitness's feature names end with the point histograms' (its last values).
bool endsWithPointHistograms(SupervisedMethod method, const FeatureOrigin& origin,
                             const PointHistogramConfig& config) {
  const std::vector<std::string> histogram = pointHistogramFeatureNames(config);
  return featureKindOf(method) == FeatureKind::kRegistrationFitness &&
         origin.names.size() > histogram.size() &&
         std::equal(histogram.begin(), histogram.end(), origin.names.end() - histogram.size());
}

// Whether svm_fitness's features hold its registrations' inlier shares (readRegistrationFeatures
// names them with inlierShareFeatureName).
bool namesInlierShares(const FeatureOrigin& origin) {
  return std::any_of(origin.names.begin(), origin.names.end(), isInlierShareFeatureName);
}

}  // namespace

struct SupervisedClassifier::Impl {
  SupervisedMethod method = SupervisedMethod::kKnn;
  SupervisedConfig config;
  std::vector<std::string> labels;
  TrainingSummary training;
  FeatureOrigin origin;
  /// svm_fitness: whether its feature names end with the point histograms' (set with origin).
  bool point_histograms = false;
  /// svm_fitness: whether its features hold the inlier shares (set with origin).
  bool inlier_shares = false;
  /// Each feature is used as (value - offset) * scale: standardised (kNN's option: offset the
  /// training mean, scale 1 / deviation) or, for the SVM, mapped to [0, 1] over the training
  /// set (offset the minimum, scale 1 / range), as libsvm's guide advises: a histogram bin that
  /// is almost always empty in training would otherwise be blown up by a tiny deviation.
  bool standardize = false;
  std::vector<float> offset;
  std::vector<float> scale;
  cv::Ptr<cv::ml::StatModel> model;  ///< what the file keeps
  /// What answers: OpenCV's answers, computed faster; one of the two, by method.
  std::optional<KnnPredictor> knn_predictor;
  std::optional<RbfSvmPredictor> svm_predictor;

  /// The model and its predictor; false when it is no one-vs-one RBF SVM of the labels.
  bool setSvm(const cv::Ptr<cv::ml::SVM>& svm) {
    model = svm;
    svm_predictor = RbfSvmPredictor::from(*svm, static_cast<int>(labels.size()));
    return svm_predictor.has_value();
  }

  std::size_t size() const {
    return featureKindOf(method) == FeatureKind::kRegistrationFitness
               ? origin.names.size()
               : featureSize(featureKindOf(method), config.histograms);
  }

  cv::Mat prepare(const std::vector<float>& features) const {
    if (features.size() != size()) {
      throw std::invalid_argument("a feature vector of " + std::to_string(features.size()) +
                                  " values, the classifier takes " + std::to_string(size()));
    }
    cv::Mat row(1, static_cast<int>(features.size()), CV_32F);
    for (std::size_t i = 0; i < features.size(); ++i) {
      row.at<float>(static_cast<int>(i)) =
          standardize ? (features[i] - offset[i]) * scale[i] : features[i];
    }
    return row;
  }
};

SupervisedClassifier::SupervisedClassifier() : impl_(std::make_unique<Impl>()) {}
SupervisedClassifier::SupervisedClassifier(SupervisedClassifier&&) noexcept = default;
SupervisedClassifier& SupervisedClassifier::operator=(SupervisedClassifier&&) noexcept = default;
SupervisedClassifier::~SupervisedClassifier() = default;

SupervisedMethod SupervisedClassifier::method() const { return impl_->method; }
const SupervisedConfig& SupervisedClassifier::config() const { return impl_->config; }
const std::vector<std::string>& SupervisedClassifier::labels() const { return impl_->labels; }
const TrainingSummary& SupervisedClassifier::training() const { return impl_->training; }
const FeatureOrigin& SupervisedClassifier::featureOrigin() const { return impl_->origin; }

bool SupervisedClassifier::takesPointHistograms() const { return impl_->point_histograms; }

bool SupervisedClassifier::takesInlierShares() const { return impl_->inlier_shares; }

std::vector<float> SupervisedClassifier::fitnessFeatures(std::vector<float> fitness,
                                                         const Cloud& object) const {
  if (takesPointHistograms()) {
    const std::vector<float> histogram = pointHistogramFeatures(object, impl_->config.histograms);
    fitness.insert(fitness.end(), histogram.begin(), histogram.end());
  }
  return fitness;
}

std::vector<float> SupervisedClassifier::features(const Cloud& object) const {
  return objectFeatures(object, featureKindOf(impl_->method), impl_->config.histograms);
}

std::string SupervisedClassifier::predict(const std::vector<float>& features) const {
  return predictWithScore(features).label;
}

SupervisedPrediction SupervisedClassifier::predictWithScore(
    const std::vector<float>& features) const {
  return predictWithScores({features}).front();
}

std::vector<SupervisedPrediction> SupervisedClassifier::predictWithScores(
    const std::vector<std::vector<float>>& features) const {
  std::vector<SupervisedPrediction> predictions;
  predictions.reserve(features.size());
  if (features.empty()) {
    return predictions;
  }
  cv::Mat rows(static_cast<int>(features.size()), static_cast<int>(impl_->size()), CV_32F);
  for (std::size_t r = 0; r < features.size(); ++r) {
    impl_->prepare(features[r]).copyTo(rows.row(static_cast<int>(r)));
  }
  const auto add = [&](long index, double score) {
    if (index < 0 || index >= static_cast<long>(impl_->labels.size())) {
      throw std::runtime_error("the classifier answered an unknown class " +
                               std::to_string(index));
    }
    predictions.push_back({impl_->labels[static_cast<std::size_t>(index)], score});
  };
  if (impl_->knn_predictor) {
    // The score: the share of the neighbours that voted for the answer.
    const double neighbours = impl_->knn_predictor->neighbours();
    for (const KnnPredictor::Answer& answer : impl_->knn_predictor->predict(rows)) {
      add(std::lround(answer.response), answer.votes / neighbours);
    }
  } else {
    // The score: the share of its one-vs-one duels the answer won.
    const double duels = static_cast<double>(impl_->labels.size() - 1);
    for (const RbfSvmPredictor::Answer& answer : impl_->svm_predictor->predict(rows)) {
      add(answer.label, answer.votes / duels);
    }
  }
  return predictions;
}

SupervisedClassifier SupervisedClassifier::train(SupervisedMethod method,
                                                 const SupervisedConfig& config,
                                                 const std::vector<std::vector<float>>& features,
                                                 const std::vector<std::string>& labels,
                                                 TrainingSummary* summary,
                                                 const FeatureOrigin& origin) {
  validate(config);
  const bool named = featureKindOf(method) == FeatureKind::kRegistrationFitness;
  config::require(!named || !origin.names.empty(),
                  "svm_fitness needs the names of its features (their registration runs)");
  config::require(!features.empty(), "no training objects");
  config::require(features.size() == labels.size(), "features and labels differ in number");
  const auto start = std::chrono::steady_clock::now();

  SupervisedClassifier classifier;
  Impl& impl = *classifier.impl_;
  impl.method = method;
  impl.config = config;
  impl.labels = labels;
  if (named) {
    impl.origin = origin;
    impl.point_histograms = endsWithPointHistograms(method, origin, config.histograms);
    impl.inlier_shares = namesInlierShares(origin);
  }
  std::sort(impl.labels.begin(), impl.labels.end());
  impl.labels.erase(std::unique(impl.labels.begin(), impl.labels.end()), impl.labels.end());
  config::require(impl.labels.size() >= 2, "training needs objects of at least two classes, got " +
                                       std::to_string(impl.labels.size()));

  const std::size_t columns = impl.size();
  cv::Mat samples = toMat(features, columns);
  cv::Mat responses(static_cast<int>(labels.size()), 1, CV_32S);
  for (std::size_t r = 0; r < labels.size(); ++r) {
    responses.at<int>(static_cast<int>(r)) = static_cast<int>(
        std::lower_bound(impl.labels.begin(), impl.labels.end(), labels[r]) - impl.labels.begin());
  }

  impl.standardize = method != SupervisedMethod::kKnn || config.knn.standardize;
  impl.offset.assign(columns, 0.0f);
  impl.scale.assign(columns, 1.0f);
  if (impl.standardize) {
    for (std::size_t c = 0; c < columns; ++c) {
      const cv::Mat column = samples.col(static_cast<int>(c));
      double spread = 0.0;
      if (method == SupervisedMethod::kKnn) {
        cv::Scalar mean, deviation;
        cv::meanStdDev(column, mean, deviation);
        impl.offset[c] = static_cast<float>(mean[0]);
        spread = deviation[0];
      } else {
        double low = 0.0, high = 0.0;
        cv::minMaxLoc(column, &low, &high);
        impl.offset[c] = static_cast<float>(low);
        spread = high - low;
      }
      impl.scale[c] = spread > 1e-12 ? static_cast<float>(1.0 / spread) : 1.0f;
      samples.col(static_cast<int>(c)) = (column - impl.offset[c]) * impl.scale[c];
    }
  }
  if (classifier.takesPointHistograms()) {
    // svm_fitness's shape values, weighted after scaling; the weight stays in `scale`.
    const float weight = static_cast<float>(config.svm_fitness.histogram_weight);
    const std::size_t histogram = featureSize(FeatureKind::kPointHistograms, config.histograms);
    for (std::size_t c = columns - histogram; c < columns; ++c) {
      impl.scale[c] *= weight;
      samples.col(static_cast<int>(c)) *= weight;
    }
  }

  TrainingSummary& training = impl.training;
  training.objects = features.size();
  if (method == SupervisedMethod::kKnn) {
    cv::Ptr<cv::ml::KNearest> knn = cv::ml::KNearest::create();
    knn->setDefaultK(config.knn.k);
    knn->setIsClassifier(true);
    knn->train(samples, cv::ml::ROW_SAMPLE, responses);
    impl.model = knn;
    cv::Mat float_responses;
    responses.convertTo(float_responses, CV_32F);
    impl.knn_predictor.emplace(samples, float_responses, config.knn.k);
  } else {
    const SvmConfig& svm = config.svm;
    // The grid search's objects: all, or a stratified sample of them.
    cv::Mat search_samples = samples, search_responses = responses;
    if (svm.search_objects > 0 && svm.search_objects < static_cast<std::size_t>(samples.rows)) {
      search_samples = cv::Mat();
      search_responses = cv::Mat();
      for (const int r : stratifiedSample(responses, svm.search_objects, svm.folds, svm.seed)) {
        search_samples.push_back(samples.row(r));
        search_responses.push_back(responses.row(r));
      }
    }
    training.search_objects = static_cast<std::size_t>(search_samples.rows);
    const std::vector<int> fold = stratifiedFolds(search_responses, svm.folds, svm.seed);
    double best_nu = svm.nu.front(), best_log2_gamma = svm.log2_gamma_min, best = -1.0;
    const auto search = [&](const std::vector<double>& nus, const std::vector<double>& log2s) {
      std::vector<std::pair<double, double>> grid;  // (nu, log2 gamma)
      for (const double nu : nus) {
        for (const double log2_gamma : log2s) {
          grid.emplace_back(nu, log2_gamma);
        }
      }
      // The pairs train independently: one per core, then chosen in grid order as one loop
      // would, so the choice does not depend on the thread count.
      std::vector<double> accuracies(grid.size(), 0.0);
      parallelFor(grid.size(), 0, 1, [&](std::size_t i) {
        accuracies[i] = crossValidate(search_samples, search_responses, fold, svm.folds,
                                      grid[i].first, std::exp2(grid[i].second));
      });
      for (std::size_t i = 0; i < grid.size(); ++i) {
        ++training.grid_points;
        // Among equals the larger nu: the softer margin generalises better from the few
        // objects a fold has.
        if (accuracies[i] > best || (accuracies[i] == best && grid[i].first > best_nu)) {
          best = accuracies[i];
          best_nu = grid[i].first;
          best_log2_gamma = grid[i].second;
        }
      }
    };
    std::vector<double> log2s;
    for (double g = svm.log2_gamma_min; g <= svm.log2_gamma_max + 1e-9; g += svm.log2_gamma_step) {
      log2s.push_back(g);
    }
    search(svm.nu, log2s);
    double step = svm.log2_gamma_step;
    for (std::size_t refinement = 0; refinement < svm.refinements; ++refinement) {
      step /= 2.0;
      std::vector<double> nus;
      for (const double factor : {0.7, 1.0, 1.4}) {
        nus.push_back(std::min(1.0, best_nu * factor));
      }
      search(nus, {best_log2_gamma - step, best_log2_gamma, best_log2_gamma + step});
    }
    cv::Ptr<cv::ml::SVM> model = makeSvm(best_nu, std::exp2(best_log2_gamma));
    if (best <= 0.0 || !model->train(samples, cv::ml::ROW_SAMPLE, responses) ||
        !model->isTrained()) {
      throw std::invalid_argument(infeasibleNuMessage(impl.labels, responses, svm.nu));
    }
    if (!impl.setSvm(model)) {
      throw std::logic_error("a trained nu-SVM that RbfSvmPredictor does not take");
    }
    training.nu = best_nu;
    training.gamma = std::exp2(best_log2_gamma);
    training.cross_validation = best;
  }
  training.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (summary != nullptr) {
    *summary = training;
  }
  return classifier;
}

void SupervisedClassifier::save(const std::filesystem::path& file) const {
  const Impl& impl = *impl_;
  std::string content;
  try {
    // Built in memory, in the format the name asks for, then written through a checked,
    // flushed temporary file: OpenCV's own writer reports no full disk.
    cv::FileStorage storage(file.extension().string().empty() ? ".yml" : file.extension().string(),
                            cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    storage << "format" << kFormat << "version" << kVersion
            << "method" << supervisedMethodName(impl.method)
            << "features" << featureKindName(featureKindOf(impl.method))
            << "feature_size" << static_cast<int>(impl.size());
    writeHistogramConfig(storage, impl.config.histograms);
    storage << "k" << impl.config.knn.k << "standardize" << impl.standardize;
    storage << "labels" << "[";
    for (const std::string& label : impl.labels) {
      storage << label;
    }
    storage << "]";
    storage << "feature_names" << "[";
    for (const std::string& name : impl.origin.names) {
      storage << name;
    }
    storage << "]";
    // write(), not <<: a string starting with '{' or '[' would open a structure.
    storage.write("feature_source", impl.origin.source);
    storage << "offset" << impl.offset << "scale" << impl.scale;
    storage << "training" << "{" << "objects" << static_cast<int>(impl.training.objects)
            << "seconds" << impl.training.seconds << "nu" << impl.training.nu << "gamma"
            << impl.training.gamma << "cross_validation" << impl.training.cross_validation
            << "grid_points" << static_cast<int>(impl.training.grid_points)
            << "search_objects" << static_cast<int>(impl.training.search_objects) << "}";
    storage << "model" << "{";
    impl.model->write(storage);
    storage << "}";
    content = storage.releaseAndGetString();
  } catch (const cv::Exception& error) {
    throw std::runtime_error(file.string() + ": cannot write: " + error.what());
  }
  writeFileAtomically(file, content, "classifier");
}

SupervisedClassifier SupervisedClassifier::load(const std::filesystem::path& file) {
  const auto fail = [&](const std::string& what) -> std::runtime_error {
    return std::runtime_error(file.string() + ": " + what);
  };
  if (std::filesystem::is_directory(file)) {
    throw fail("is a folder (class models?); the supervised methods (knn, svm, svm_esf, "
               "svm_fitness) need a classifier file written by train_classifier");
  }
  if (!std::filesystem::is_regular_file(file)) {
    throw fail("no such classifier file");
  }
  SupervisedClassifier classifier;
  Impl& impl = *classifier.impl_;
  try {
    cv::FileStorage storage(file.string(), cv::FileStorage::READ);
    if (!storage.isOpened() || static_cast<std::string>(storage["format"]) != kFormat) {
      throw fail("not a granular classifier file (train_classifier writes them)");
    }
    if (static_cast<int>(storage["version"]) != kVersion) {
      throw fail("written by another version of granular (format version " +
                 std::to_string(static_cast<int>(storage["version"])) + ", this one reads " +
                 std::to_string(kVersion) + ")");
    }
    const auto method = supervisedMethodFromName(storage["method"]);
    if (!method) {
      throw fail("unknown method '" + static_cast<std::string>(storage["method"]) + "'");
    }
    impl.method = *method;
    const cv::FileNode h = storage["histograms"];
    PointHistogramConfig& histograms = impl.config.histograms;
    histograms.sample_points = static_cast<std::size_t>(static_cast<int>(h["sample_points"]));
    histograms.neighbours = static_cast<std::size_t>(static_cast<int>(h["neighbours"]));
    histograms.neighbour_radius = h["neighbour_radius"];
    histograms.bins = static_cast<std::size_t>(static_cast<int>(h["bins"]));
    histograms.cylinder_height = h["cylinder_height"];
    histograms.cylinder_radius = h["cylinder_radius"];
    histograms.cylinder_slices = static_cast<std::size_t>(static_cast<int>(h["cylinder_slices"]));
    const auto scatter = scatterDefinitionFromName(h["scatter"]);
    if (!scatter) {
      throw fail("histograms.scatter: unknown value");
    }
    histograms.scatter = *scatter;
    histograms.seed = static_cast<std::uint32_t>(static_cast<int>(h["seed"]));
    validate(histograms);
    // Absent from files written before svm_fitness; the other methods need none.
    for (const cv::FileNode& name : storage["feature_names"]) {
      impl.origin.names.push_back(static_cast<std::string>(name));
    }
    if (!storage["feature_source"].empty()) {
      impl.origin.source = static_cast<std::string>(storage["feature_source"]);
    }
    if (featureKindOf(impl.method) == FeatureKind::kRegistrationFitness &&
        impl.origin.names.empty()) {
      throw fail("svm_fitness without the names of its features");
    }
    impl.point_histograms = endsWithPointHistograms(impl.method, impl.origin, histograms);
    impl.inlier_shares = namesInlierShares(impl.origin);
    if (static_cast<int>(storage["feature_size"]) != static_cast<int>(impl.size())) {
      throw fail("its feature size " + std::to_string(static_cast<int>(storage["feature_size"])) +
                 " does not match its feature configuration (" + std::to_string(impl.size()) +
                 ")");
    }
    impl.config.knn.k = storage["k"];
    impl.standardize = static_cast<int>(storage["standardize"]) != 0;
    for (const cv::FileNode& label : storage["labels"]) {
      impl.labels.push_back(static_cast<std::string>(label));
    }
    storage["offset"] >> impl.offset;
    storage["scale"] >> impl.scale;
    const cv::FileNode t = storage["training"];
    impl.training.objects = static_cast<std::size_t>(static_cast<int>(t["objects"]));
    impl.training.seconds = t["seconds"];
    impl.training.nu = t["nu"];
    impl.training.gamma = t["gamma"];
    impl.training.cross_validation = t["cross_validation"];
    impl.training.grid_points = static_cast<std::size_t>(static_cast<int>(t["grid_points"]));
    // Absent from models saved before the search could use a sample: all objects.
    impl.training.search_objects =
        t["search_objects"].empty() ? impl.training.objects
                                    : static_cast<std::size_t>(static_cast<int>(t["search_objects"]));
    if (impl.offset.size() != impl.size() || impl.scale.size() != impl.size() ||
        impl.labels.size() < 2) {
      throw fail("its standardisation or labels are incomplete");
    }
    if (impl.method == SupervisedMethod::kKnn) {
      cv::Ptr<cv::ml::KNearest> knn = cv::ml::KNearest::create();
      knn->read(storage["model"]);
      impl.model = knn;
    } else {
      cv::Ptr<cv::ml::SVM> svm = cv::ml::SVM::create();
      svm->read(storage["model"]);
      impl.model = svm;
    }
    if (!impl.model->isTrained() || impl.model->getVarCount() != static_cast<int>(impl.size())) {
      throw fail("its model is missing or takes another number of features");
    }
    if (impl.method == SupervisedMethod::kKnn) {
      // The training rows and responses KNearest wrote (it has no getter for them).
      cv::Mat samples, responses;
      storage["model"]["samples"] >> samples;
      storage["model"]["responses"] >> responses;
      impl.knn_predictor.emplace(samples, responses, impl.config.knn.k);
    } else if (!impl.setSvm(impl.model.dynamicCast<cv::ml::SVM>())) {
      throw fail("its SVM is not a one-vs-one RBF classifier of its " +
                 std::to_string(impl.labels.size()) + " labels");
    }
  } catch (const cv::Exception&) {
    // OpenCV's own text names a parser function, which tells a user nothing.
    throw fail("not a complete classifier file (cut short, or not written by train_classifier)");
  } catch (const std::invalid_argument& error) {
    throw fail(error.what());
  }
  return classifier;
}

}  // namespace granular
