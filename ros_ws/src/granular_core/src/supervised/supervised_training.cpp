// SupervisedClassifier::train: the features scaled, kNN stored or the nu-SVM's (nu, gamma)
// chosen by a stratified, cross-validated grid search and trained on every object.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "classifier_impl.h"
#include "granular_core/parallel.h"

namespace granular {
namespace {

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

}  // namespace

using supervised_detail::endsWithPointHistograms;
using supervised_detail::namesInlierShares;

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

}  // namespace granular
