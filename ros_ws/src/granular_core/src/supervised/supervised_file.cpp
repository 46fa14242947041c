// The classifier file SupervisedClassifier::save writes and load reads (OpenCV's FileStorage
// YAML): format and version, method, config, labels, training summary, feature origin and
// scaling, and the OpenCV model.
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "classifier_impl.h"
#include "granular_core/dataset/atomic_file.h"

namespace granular {
namespace {

constexpr const char* kFormat = "granular_supervised_classifier";
constexpr int kVersion = 1;

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

using supervised_detail::endsWithPointHistograms;
using supervised_detail::namesInlierShares;

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
