// The registration results file: what is written reads back the same, and what is not such a
// file is refused with a message naming it.
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/dataset/registration_results.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

using RegistrationResultsTest = TemporaryFolderTest;

// Two objects against two models: one pair that ran and converged, one that did not run.
RegistrationResultsFile twoObjects(bool transforms) {
  RegistrationResultsFile results;
  results.method = "icp";
  results.preset = "tuned";
  results.parameters = R"({"max_correspondence_distance":0.1,"max_iterations":30})";
  results.models = {"Sedan", "SUV"};
  results.inlier_radii = std::vector<double>{0.03, 0.06, 0.1, 0.2};
  results.seconds = 1.25;
  results.threads = 4;
  results.transforms = transforms;
  RegistrationPairRecord ran;
  ran.fitness = 0.0123;
  ran.converged = true;
  ran.state = "transform";
  ran.iterations = 7;
  ran.inlier_shares = {0.5f, 0.75f, 0.016393442f, 1.0f};
  if (transforms) {
    ran.transform = std::array<float, 16>{1, 0, 0, 0.25f, 0, 1, 0, -0.5f, 0, 0, 1, 0, 0, 0, 0, 1};
  }
  RegistrationPairRecord not_run;
  not_run.state = "too_few_points";
  RegistrationPairRecord rejected = ran;
  rejected.fitness.reset();
  rejected.inlier_shares.clear();
  rejected.rejected = true;
  results.objects.push_back({"Sedan-1-1.pcd", "Sedan", 120, 100, {ran, rejected}, {}});
  results.objects[0].predictions = {std::string("Sedan"), std::string("Sedan"), std::nullopt};
  results.objects.push_back({"unlabelled.pcd", std::nullopt, 2, 2, {not_run, not_run}, {}});
  results.criteria[1] = {1, 1, 1, 1, 1.0};
  results.warnings = {"1 object(s) of classes without a model"};
  return results;
}

void expectSame(const RegistrationResultsFile& a, const RegistrationResultsFile& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.preset, b.preset);
  EXPECT_EQ(a.parameters, b.parameters);
  EXPECT_EQ(a.models, b.models);
  EXPECT_EQ(a.inlier_radii, b.inlier_radii);
  EXPECT_EQ(a.seconds, b.seconds);
  EXPECT_EQ(a.threads, b.threads);
  EXPECT_EQ(a.transforms, b.transforms);
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    const RegistrationObjectRecord& x = a.objects[i];
    const RegistrationObjectRecord& y = b.objects[i];
    EXPECT_EQ(x.file, y.file);
    EXPECT_EQ(x.true_label, y.true_label);
    EXPECT_EQ(x.points, y.points);
    EXPECT_EQ(x.points_used, y.points_used);
    EXPECT_EQ(x.predictions, y.predictions);
    ASSERT_EQ(x.per_model.size(), y.per_model.size());
    for (std::size_t m = 0; m < x.per_model.size(); ++m) {
      const RegistrationPairRecord& p = x.per_model[m];
      const RegistrationPairRecord& q = y.per_model[m];
      EXPECT_EQ(p.fitness, q.fitness) << x.file << " " << m;
      EXPECT_EQ(p.converged, q.converged);
      EXPECT_EQ(p.state, q.state);
      EXPECT_EQ(p.iterations, q.iterations);
      EXPECT_EQ(p.inlier_shares, q.inlier_shares);  // floats, bit for bit
      EXPECT_EQ(p.rejected, q.rejected);
      EXPECT_EQ(p.transform, q.transform);
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_EQ(a.criteria[c].predicted, b.criteria[c].predicted);
    EXPECT_EQ(a.criteria[c].missing, b.criteria[c].missing);
    EXPECT_EQ(a.criteria[c].labelled, b.criteria[c].labelled);
    EXPECT_EQ(a.criteria[c].correct, b.criteria[c].correct);
    EXPECT_EQ(a.criteria[c].accuracy, b.criteria[c].accuracy);
  }
  EXPECT_EQ(a.warnings, b.warnings);
}

TEST_F(RegistrationResultsTest, WhatIsWrittenReadsBackTheSame) {
  for (const bool transforms : {false, true}) {
    const RegistrationResultsFile written = twoObjects(transforms);
    const fs::path file = root_ / "results.json";
    writeRegistrationResults(file, written);
    expectSame(readRegistrationResults(file), written);
  }
}

TEST_F(RegistrationResultsTest, FloatsAreWrittenAtMostNineDigitsLong) {
  const fs::path file = root_ / "results.json";
  writeRegistrationResults(file, twoObjects(false));
  const std::string text = read(file);
  EXPECT_NE(text.find("0.016393442"), std::string::npos);
  EXPECT_EQ(text.find("0.0163934417"), std::string::npos);  // not the widened float
  EXPECT_NE(text.find("\"true_label\": null"), std::string::npos);
  EXPECT_EQ(text.find("\"transform\":"), std::string::npos);  // only when asked
}

TEST_F(RegistrationResultsTest, AFileWithoutInlierRadiiIsAnOlderOneWithoutShares) {
  const fs::path file = write("old.json", R"({"method": "ndt", "parameters": {},
      "models": ["Sedan"],
      "objects": [{"file": "Sedan-1-1.pcd", "points": 9,
                   "per_model": {"Sedan": {"fitness": 0.5}}}]})");
  const RegistrationResultsFile read = readRegistrationResults(file);
  EXPECT_FALSE(read.inlier_radii.has_value());
  EXPECT_EQ(read.preset, "");
  ASSERT_EQ(read.objects.size(), 1u);
  EXPECT_EQ(read.objects[0].per_model[0].fitness, 0.5);
  EXPECT_TRUE(read.objects[0].per_model[0].inlier_shares.empty());
}

std::string errorReading(const fs::path& file) {
  try {
    readRegistrationResults(file);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST_F(RegistrationResultsTest, WhatIsNotAResultsFileIsRefusedNamingTheFile) {
  const fs::path missing = root_ / "missing.json";
  EXPECT_EQ(errorReading(missing), missing.string() + ": cannot read it");
  const fs::path models_only = write("models_only.json", R"({"models": ["Sedan"]})");
  EXPECT_EQ(errorReading(models_only),
            models_only.string() +
                ": not a classify_registration results file (no models or objects)");
  const fs::path no_pair = write("no_pair.json", R"({"method": "icp", "parameters": {},
      "models": ["Sedan", "SUV"],
      "objects": [{"file": "a.pcd", "points": 3, "per_model": {"Sedan": {"fitness": null}}}]})");
  const std::string no_pair_error = errorReading(no_pair);
  EXPECT_EQ(no_pair_error.rfind(no_pair.string() +
                                    ": not a classify_registration results file (",
                                0),
            0u)
      << no_pair_error;
  EXPECT_NE(no_pair_error.find("SUV"), std::string::npos) << no_pair_error;
  const fs::path not_json = write("not_json.json", "fitness: 1\n");
  EXPECT_EQ(errorReading(not_json).rfind(not_json.string() + ": not a classify_registration", 0),
            0u);
}

TEST_F(RegistrationResultsTest, PairsThatDoNotMatchTheModelsAreNotWritten) {
  RegistrationResultsFile results = twoObjects(false);
  results.objects[0].per_model.pop_back();
  const fs::path file = root_ / "results.json";
  EXPECT_THROW(writeRegistrationResults(file, results), std::invalid_argument);
  EXPECT_FALSE(fs::exists(file));
}

}  // namespace
}  // namespace granular
