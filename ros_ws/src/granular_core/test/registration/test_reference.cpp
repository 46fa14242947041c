// How a run's results are compared with the report's loop: what bench_registration prints.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/registration/reference.h"

namespace granular {
namespace {

PairResult converged(double fitness) {
  PairResult pair;
  pair.state = RegistrationState::kTransform;
  pair.fitness = fitness;
  pair.iterations = 5;
  return pair;
}

PairResult notConverged(double fitness) {
  PairResult pair = converged(fitness);
  pair.state = RegistrationState::kIterations;
  return pair;
}

// Two objects against two models (Sedan, SUV).
std::vector<std::vector<PairResult>> reference() {
  return {{converged(0.01), notConverged(0.02)}, {converged(0.03), converged(0.02)}};
}

TEST(CompareWithReferenceTest, TheSameResultsDifferNowhere) {
  const ReferenceComparison same = compareWithReference(reference(), reference());
  EXPECT_EQ(same.different_predictions, 0u);
  EXPECT_EQ(same.different_pairs, 0u);
  EXPECT_EQ(same.rejected_pairs, 0u);
}

TEST(CompareWithReferenceTest, ADifferentFitnessThatKeepsThePredictionsIsAPairNotAnObject) {
  std::vector<std::vector<PairResult>> ours = reference();
  ours[0][1].fitness = 0.025;  // still the worse model
  const ReferenceComparison comparison = compareWithReference(reference(), ours);
  EXPECT_EQ(comparison.different_predictions, 0u);
  EXPECT_EQ(comparison.different_pairs, 1u);
}

TEST(CompareWithReferenceTest, AnotherWinnerIsADifferentPrediction) {
  std::vector<std::vector<PairResult>> ours = reference();
  ours[1][0].fitness = 0.001;  // criterion 2 and 3 now pick Sedan for object 2
  ours[0][0].iterations = 6;   // and a pair of object 1 differs in iterations only
  const ReferenceComparison comparison = compareWithReference(reference(), ours);
  EXPECT_EQ(comparison.different_predictions, 1u);
  EXPECT_EQ(comparison.different_pairs, 2u);
}

TEST(CompareWithReferenceTest, ARejectedPairIsComparedInAllButItsFitness) {
  std::vector<std::vector<PairResult>> ours = reference();
  ours[0][1].rejected = true;
  ours[0][1].fitness = std::numeric_limits<double>::infinity();
  ours[1][1].fitness = std::nan("");
  std::vector<std::vector<PairResult>> with_nan = reference();
  with_nan[1][1].fitness = std::nan("");  // NaN against NaN is the same fitness
  const ReferenceComparison comparison = compareWithReference(with_nan, ours);
  EXPECT_EQ(comparison.rejected_pairs, 1u);
  EXPECT_EQ(comparison.different_pairs, 0u);
}

TEST(Criterion2AccuracyTest, IsTheShareOfObjectsWhoseConvergedBestIsTheirLabel) {
  const std::vector<LabelledModel> models = {{"Sedan", {}}, {"SUV", {}}};
  // Object 1: only Sedan converged -> Sedan. Object 2: SUV has the lower fitness -> SUV.
  EXPECT_DOUBLE_EQ(criterion2Accuracy(reference(), {"Sedan", "Sedan"}, models), 0.5);
  EXPECT_DOUBLE_EQ(criterion2Accuracy(reference(), {"Sedan", "SUV"}, models), 1.0);
  // An object that converged nowhere has no prediction: wrong.
  std::vector<std::vector<PairResult>> none = {{notConverged(0.01), notConverged(0.02)}};
  EXPECT_DOUBLE_EQ(criterion2Accuracy(none, {"Sedan"}, models), 0.0);
  EXPECT_DOUBLE_EQ(criterion2Accuracy({}, {}, models), 0.0);
}

}  // namespace
}  // namespace granular
