// svm_fitness from classify_registration's results files (and its objects' point histograms):
// trained, saved, loaded, and refused where the results came from other registrations.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/runs/classify_supervised_run.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {

namespace fs = std::filesystem;
using testing_support::TemporaryFolderTest;

// A Sedan/Hatchback-like pair of classes: a Sedan fits the Sedan model best, but a Hatchback
// fits the Sedan model slightly better than its own (0.9 times its own fitness), as a
// one-sided fitness lets it: the lowest fitness calls every Hatchback a Sedan. Its fitness
// against the Hatchback model is still nearer its Sedan fitness than a Sedan's is, and that
// profile is what svm_fitness learns. `method` scales every fitness, as methods differ.
class FitnessProfileTest : public TemporaryFolderTest {
 protected:
  struct Object {
    std::string file;
    std::size_t points;
    double own;    // fitness against its own class's model, m^2
  };

  void SetUp() override {
    TemporaryFolderTest::SetUp();
    std::mt19937 random(5);
    std::uniform_real_distribution<double> own(0.004, 0.04);
    std::uniform_int_distribution<std::size_t> points(50, 2000);
    for (int i = 0; i < 80; ++i) {
      const std::string label = i % 2 == 0 ? "Sedan" : "Hatchback";
      (i < 60 ? train_ : test_).push_back(
          {label + "-" + std::to_string(1000 + i) + "-1.pcd", points(random), own(random)});
    }
  }

  // The fitness of `object` against `model`.
  static double fitness(const Object& object, const std::string& model) {
    const bool sedan = object.file.rfind("Sedan", 0) == 0;
    if (model == "Sedan") {
      return sedan ? object.own : 0.9 * object.own;
    }
    return sedan ? 1.6 * object.own : object.own;
  }

  // classify_registration's results file of `objects` for a method, every fitness times
  // `scale`; `unregistered` objects (by index) have no fitness against the Hatchback model.
  // Each registered pair's inlier shares are share_(object, model) at every radius.
  fs::path results(const std::string& name, const std::string& method,
                   const std::vector<Object>& objects, double scale,
                   const std::vector<std::size_t>& unregistered = {}) const {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < objects.size(); ++i) {
      nlohmann::json per_model;
      for (const std::string model : {"Hatchback", "Sedan"}) {
        const bool missing = model == std::string("Hatchback") &&
                             std::find(unregistered.begin(), unregistered.end(), i) !=
                                 unregistered.end();
        per_model[model] = {{"converged", true},
                            {"fitness", missing ? nlohmann::json(nullptr)
                                                : nlohmann::json(scale * fitness(objects[i], model))}};
        if (!missing) {
          per_model[model]["inlier_shares"] = std::vector<float>(4, share_(objects[i], model));
        }
      }
      list.push_back({{"file", objects[i].file},
                      {"points", objects[i].points},
                      {"per_model", per_model}});
    }
    const nlohmann::json document = {{"method", method},
                                     {"preset", "tuned"},
                                     {"parameters", {{"max_iterations", 30}}},
                                     {"models", {"Hatchback", "Sedan"}},
                                     {"inlier_radii", {0.03, 0.06, 0.1, 0.2}},
                                     {"seconds", 1.5},
                                     {"objects", list}};
    return write(name, document.dump());
  }

  // results() of `objects` by ICP, with one fitness (0.01 m^2) for every object and model.
  fs::path alikeResults(const std::string& name, const std::vector<Object>& objects) const {
    nlohmann::json document = nlohmann::json::parse(read(results(name, "icp", objects, 1.0)));
    for (nlohmann::json& object : document["objects"]) {
      object["per_model"]["Hatchback"]["fitness"] = 0.01;
      object["per_model"]["Sedan"]["fitness"] = 0.01;
    }
    return write(name, document.dump());
  }

  // Objects `run` classified right.
  static std::size_t right(const SupervisedRun& run) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < run.files.size(); ++i) {
      count += run.predicted[i] == run.true_labels[i];
    }
    return count;
  }

  std::vector<Object> train_, test_;
  std::function<float(const Object&, const std::string&)> share_ =
      [](const Object&, const std::string&) { return 0.5f; };
};

TEST_F(FitnessProfileTest, LearnsWhatTheLowestFitnessGetsWrong) {
  // The lowest fitness is right for the Sedans only.
  std::size_t lowest_right = 0;
  for (const Object& object : test_) {
    const bool sedan = object.file.rfind("Sedan", 0) == 0;
    const bool says_sedan = fitness(object, "Sedan") < fitness(object, "Hatchback");
    lowest_right += says_sedan == sedan;
  }
  EXPECT_EQ(lowest_right, test_.size() / 2);

  SupervisedConfig config;
  config.svm.refinements = 1;
  config.svm_fitness.inlier_shares = false;
  config.svm_fitness.histogram_weight = 0.0;  // the fitness alone: no objects to read
  const TrainingRun training =
      trainOnRegistration({results("train_icp.json", "icp", train_, 1.0),
                           results("train_ndt.json", "ndt", train_, 3.0)},
                          config);
  EXPECT_EQ(training.summary.objects, train_.size());
  EXPECT_EQ(training.classifier.featureOrigin().names,
            (std::vector<std::string>{"icp/tuned:Hatchback", "icp/tuned:Sedan",
                                      "ndt/tuned:Hatchback", "ndt/tuned:Sedan", "log_points"}));
  const fs::path model = root_ / "svm_fitness.yml";
  training.classifier.save(model);
  const SupervisedClassifier loaded = SupervisedClassifier::load(model);
  EXPECT_EQ(loaded.featureOrigin().names, training.classifier.featureOrigin().names);
  EXPECT_EQ(loaded.featureOrigin().source, training.classifier.featureOrigin().source);

  const SupervisedRun run = classifyRegistrationResults(
      loaded, {results("test_icp.json", "icp", test_, 1.0),
               results("test_ndt.json", "ndt", test_, 3.0)});
  ASSERT_EQ(run.files.size(), test_.size());
  EXPECT_DOUBLE_EQ(run.registration_seconds, 3.0);
  for (std::size_t i = 0; i < test_.size(); ++i) {
    EXPECT_EQ(run.files[i], test_[i].file);
    EXPECT_EQ(run.points[i], test_[i].points);
    EXPECT_EQ(run.predicted[i], run.true_labels[i]) << test_[i].file;
  }
  // A cloud alone does not give its features.
  EXPECT_THROW(loaded.features(Cloud()), std::invalid_argument);
}

TEST_F(FitnessProfileTest, ResultsOfOtherRegistrationsAreRefused) {
  SupervisedConfig config;
  config.svm.refinements = 0;
  config.svm_fitness.histogram_weight = 0.0;
  const TrainingRun training = trainOnRegistration(
      {results("train_icp.json", "icp", train_, 1.0), results("train_ndt.json", "ndt", train_, 3.0)},
      config);
  const fs::path icp = results("test_icp.json", "icp", test_, 1.0);
  const fs::path ndt = results("test_ndt.json", "ndt", test_, 3.0);
  const auto refusal = [&](const std::vector<fs::path>& files) -> std::string {
    try {
      classifyRegistrationResults(training.classifier, files);
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  // The methods in another order, or one of them missing.
  EXPECT_NE(refusal({ndt, icp}).find(ndt.string() + ": registered with other method"),
            std::string::npos)
      << refusal({ndt, icp});
  EXPECT_NE(refusal({icp}).find("learnt from 2 registration results (icp, ndt), got 1"),
            std::string::npos)
      << refusal({icp});
  // Other parameters.
  nlohmann::json other = nlohmann::json::parse(read(ndt));
  other["parameters"]["max_iterations"] = 35;
  const fs::path retuned = write("retuned.json", other.dump());
  EXPECT_NE(refusal({icp, retuned}).find("other parameters"), std::string::npos);
  // Files of two objects folders.
  std::vector<Object> fewer(test_.begin(), test_.end() - 1);
  const fs::path short_ndt = results("short_ndt.json", "ndt", fewer, 3.0);
  EXPECT_NE(refusal({icp, short_ndt}).find("lists other objects"), std::string::npos);
  // Written with early rejection: some models' fitness was never computed.
  nlohmann::json early = nlohmann::json::parse(read(ndt));
  early["objects"][0]["per_model"]["Sedan"]["fitness"] = nullptr;
  early["objects"][0]["per_model"]["Sedan"]["rejected"] = true;
  const fs::path rejected = write("rejected.json", early.dump());
  EXPECT_NE(refusal({icp, rejected}).find(rejected.string() + ": written with --early-rejection"),
            std::string::npos)
      << refusal({icp, rejected});
  // Written before the inlier shares were recorded, or with other radii.
  nlohmann::json older = nlohmann::json::parse(read(ndt));
  older.erase("inlier_radii");
  const fs::path unshared = write("unshared.json", older.dump());
  EXPECT_NE(refusal({icp, unshared}).find(unshared.string() + ": records no inlier shares"),
            std::string::npos)
      << refusal({icp, unshared});
  older["inlier_radii"] = {0.05, 0.1, 0.2, 0.4};
  const fs::path other_radii = write("other_radii.json", older.dump());
  EXPECT_NE(refusal({icp, other_radii}).find(other_radii.string() + ": inlier shares measured at"),
            std::string::npos)
      << refusal({icp, other_radii});
  // Not a results file at all.
  const fs::path broken = write("broken.json", "{\"models\": [\"Sedan\"]");
  EXPECT_NE(refusal({icp, broken}).find(broken.string() + ": not a classify_registration"),
            std::string::npos)
      << refusal({icp, broken});
}

// Points on a car-sized slab (a "Sedan") or in a ball (a "Hatchback"), 300 of them.
Cloud shapeOf(const std::string& label, std::mt19937& random) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Cloud cloud;
  while (cloud.size() < 300) {
    const float x = unit(random), y = unit(random), z = unit(random);
    if (label == "Sedan") {
      cloud.push_back(PointXYZIT(2.2f * x, 0.8f * y, 0.7f + 0.05f * z, 0, 0.0));
    } else if (x * x + y * y + z * z <= 1.0f) {
      cloud.push_back(PointXYZIT(0.8f * x, 0.8f * y, 0.8f + 0.8f * z, 0, 0.0));
    }
  }
  return cloud;
}

TEST_F(FitnessProfileTest, PointHistogramsTellApartWhatTheFitnessCannot) {
  // Every object fits both models alike and has as many points: the fitness values are the
  // same for both classes, so alone they can only give every object one answer. The objects'
  // shapes differ, and with the point histograms svm_fitness tells them apart.
  std::mt19937 random(3);
  for (auto* objects : {&train_, &test_}) {
    const std::string folder = objects == &train_ ? "train" : "test";
    fs::create_directories(root_ / folder);
    for (Object& object : *objects) {
      object.points = 300;
      object.own = 0.01;
      writePcdBinary(root_ / folder / object.file, shapeOf(objectClass(object.file), random));
    }
  }
  const fs::path train = alikeResults("train_icp.json", train_);
  const fs::path test = alikeResults("test_icp.json", test_);

  SupervisedConfig config;
  config.svm.refinements = 0;
  config.svm_fitness.inlier_shares = false;  // the same for both classes here
  config.svm_fitness.histogram_weight = 0.0;
  const TrainingRun fitness_only = trainOnRegistration({train}, config);
  EXPECT_FALSE(fitness_only.classifier.takesPointHistograms());
  EXPECT_EQ(right(classifyRegistrationResults(fitness_only.classifier, {test})),
            test_.size() / 2);

  config.svm_fitness.histogram_weight = 0.3;
  EXPECT_THROW(trainOnRegistration({train}, config), std::invalid_argument);  // no objects
  const fs::path model = root_ / "svm_fitness.yml";
  trainOnRegistration({train}, config, root_ / "train").classifier.save(model);
  const SupervisedClassifier loaded = SupervisedClassifier::load(model);
  EXPECT_TRUE(loaded.takesPointHistograms());
  const std::vector<std::string>& names = loaded.featureOrigin().names;
  ASSERT_EQ(names.size(), 2u + 1u + 60u);
  EXPECT_EQ(names[2], "log_points");
  EXPECT_EQ(names[3], "point_histograms:0");
  EXPECT_EQ(names.back(), "point_histograms:59");
  EXPECT_EQ(right(classifyRegistrationResults(loaded, {test}, root_ / "test")), test_.size());
  EXPECT_THROW(classifyRegistrationResults(loaded, {test}), std::invalid_argument);
}

TEST_F(FitnessProfileTest, InlierSharesTellApartWhatTheFitnessCannot) {
  // Every object has the same fitness against both models: a model that explains most of the
  // object closely but misses a part of it (a Hatchback's rear against the Sedan model's
  // trunk) can have the fitness of one that explains all of it loosely. How many points lie
  // close to each model tells the two apart.
  share_ = [](const Object& object, const std::string& model) {
    return object.file.rfind(model, 0) == 0 ? 0.8f : 0.55f;
  };
  for (auto* objects : {&train_, &test_}) {
    for (Object& object : *objects) {
      object.points = 300;
    }
  }
  const fs::path train = alikeResults("train_icp.json", train_);
  const fs::path test = alikeResults("test_icp.json", test_);
  SupervisedConfig config;
  config.svm.refinements = 0;
  config.svm_fitness.histogram_weight = 0.0;
  config.svm_fitness.inlier_shares = false;
  const TrainingRun without = trainOnRegistration({train}, config);
  EXPECT_FALSE(without.classifier.takesInlierShares());
  EXPECT_EQ(right(classifyRegistrationResults(without.classifier, {test})), test_.size() / 2);

  config.svm_fitness.inlier_shares = true;
  const fs::path model = root_ / "svm_fitness.yml";
  trainOnRegistration({train}, config).classifier.save(model);
  const SupervisedClassifier loaded = SupervisedClassifier::load(model);
  EXPECT_TRUE(loaded.takesInlierShares());
  EXPECT_EQ(loaded.featureOrigin().names.size(), 2u + 1u + 2u * 4u);
  EXPECT_EQ(right(classifyRegistrationResults(loaded, {test})), test_.size());
}

TEST_F(FitnessProfileTest, FeaturesAreLogFitnessAndLogPoints) {
  const std::vector<Object> objects = {{"Sedan-1-1.pcd", 100, 0.01}, {"Sedan-2-1.pcd", 0, 0.02}};
  const RegistrationFeatures features =
      readRegistrationFeatures({results("icp.json", "icp", objects, 1.0, {1})}, false);
  ASSERT_EQ(features.folder.features.size(), 2u);
  EXPECT_EQ(features.folder.labels, (std::vector<std::string>{"Sedan", "Sedan"}));
  const std::vector<float>& first = features.folder.features[0];
  ASSERT_EQ(first.size(), 3u);
  EXPECT_FLOAT_EQ(first[0], std::log(0.016f));   // Hatchback model
  EXPECT_FLOAT_EQ(first[1], std::log(0.01f));    // Sedan model
  EXPECT_FLOAT_EQ(first[2], std::log(100.0f));   // points
  // No fitness (registration failed) is as bad as kUnregisteredFitness; no points count as 1.
  const std::vector<float>& second = features.folder.features[1];
  EXPECT_FLOAT_EQ(second[0], std::log(static_cast<float>(kUnregisteredFitness)));
  EXPECT_FLOAT_EQ(second[2], 0.0f);
  EXPECT_EQ(registrationFitnessFeatures({{{0.0, {}}, {std::nullopt, {}}}}, 1, false),
            (std::vector<float>{static_cast<float>(std::log(kFitnessFloor)),
                                static_cast<float>(std::log(kUnregisteredFitness)), 0.0f}));
}

TEST_F(FitnessProfileTest, InlierSharesFollowAsTheirLogOdds) {
  const std::vector<Object> objects = {{"Sedan-1-1.pcd", 100, 0.01}, {"Sedan-2-1.pcd", 0, 0.02}};
  share_ = [](const Object&, const std::string& model) { return model == "Sedan" ? 1.0f : 0.0f; };
  const RegistrationFeatures features =
      readRegistrationFeatures({results("icp.json", "icp", objects, 1.0, {1})}, true);
  const std::vector<std::string>& names = features.origin.names;
  ASSERT_EQ(names.size(), 2u + 1u + 2u * 4u);
  EXPECT_EQ(names[2], "log_points");
  EXPECT_EQ(names[3], "icp/tuned:Hatchback:within_0.03m");
  EXPECT_EQ(names[6], "icp/tuned:Hatchback:within_0.2m");
  EXPECT_EQ(names[7], "icp/tuned:Sedan:within_0.03m");
  // log((s + 0.01) / (1.01 - s)): none within is log(1 / 101), all within log(101).
  const std::vector<float>& first = features.folder.features[0];
  ASSERT_EQ(first.size(), names.size());
  EXPECT_FLOAT_EQ(first[2], std::log(100.0f));
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_FLOAT_EQ(first[3 + r], -std::log(101.0f)) << r;
    EXPECT_FLOAT_EQ(first[7 + r], std::log(101.0f)) << r;
  }
  // Not registered against the Hatchback model: nothing lies near it.
  EXPECT_FLOAT_EQ(features.folder.features[1][3], -std::log(101.0f));
  EXPECT_FLOAT_EQ(registrationFitnessFeatures({{{0.01, {0.5f, 0.5f, 0.5f, 0.5f}}}}, 1, true)[2],
                  0.0f);
}

}  // namespace
}  // namespace granular
