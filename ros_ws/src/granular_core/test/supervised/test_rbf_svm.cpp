// RbfSvmPredictor against the cv::ml::SVM it reads: the same class for every sample.
#include <cmath>
#include <random>
#include <tuple>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "granular_core/supervised/rbf_svm.h"

namespace granular {
namespace {

// Overlapping Gaussian classes in `variables` dimensions, so that many samples lie near the
// boundaries, where a different rounding would change an answer.
void overlappingClasses(int classes, int variables, int count, std::mt19937& random,
                        cv::Mat& samples, cv::Mat& responses) {
  std::normal_distribution<float> noise(0.0f, 1.0f);
  // The same distance between class means in any number of dimensions.
  const float shift = 1.5f / std::sqrt(static_cast<float>(variables));
  samples.create(count, variables, CV_32F);
  responses.create(count, 1, CV_32S);
  for (int r = 0; r < count; ++r) {
    const int label = r % classes;
    responses.at<int>(r) = label;
    for (int v = 0; v < variables; ++v) {
      samples.at<float>(r, v) =
          shift * static_cast<float>((label + v) % classes) + noise(random);
    }
  }
}

TEST(RbfSvmPredictorTest, AnswersWhatOpenCvsPredictAnswersForEverySample) {
  std::mt19937 random(11);
  // 13 and 7 values: the kernel's sums run four values at a time, plus a tail.
  for (const auto& [classes, variables, svm_type] :
       {std::tuple{5, 13, cv::ml::SVM::NU_SVC}, std::tuple{2, 7, cv::ml::SVM::C_SVC},
        std::tuple{8, 60, cv::ml::SVM::NU_SVC}}) {
    cv::Mat samples, responses;
    overlappingClasses(classes, variables, 400, random, samples, responses);
    cv::Ptr<cv::ml::SVM> svm = cv::ml::SVM::create();
    svm->setType(svm_type);
    svm->setKernel(cv::ml::SVM::RBF);
    svm->setNu(0.3);
    svm->setGamma(0.7 / variables);
    ASSERT_TRUE(svm->train(samples, cv::ml::ROW_SAMPLE, responses));

    const std::optional<RbfSvmPredictor> predictor = RbfSvmPredictor::from(*svm, classes);
    ASSERT_TRUE(predictor.has_value());
    const std::optional<RbfSvmPredictor> baseline =
        RbfSvmPredictor::from(*svm, classes, RbfSvmPredictor::Instructions::kBaseline);
    ASSERT_TRUE(baseline.has_value());
    cv::Mat queries, unused;
    overlappingClasses(classes, variables, 3001, random, queries, unused);
    cv::Mat expected;
    svm->predict(queries, expected);
    const std::vector<RbfSvmPredictor::Answer> answers = predictor->predict(queries);
    ASSERT_EQ(answers.size(), 3001u);
    // AVX2 (where this machine has it) and the baseline: the same labels and the same votes,
    // from the same kernel values.
    const std::vector<RbfSvmPredictor::Answer> baseline_answers = baseline->predict(queries);
    ASSERT_EQ(baseline_answers.size(), answers.size());
    int differ = 0, wrong = 0;
    int unanimous = 0;
    for (int r = 0; r < queries.rows; ++r) {
      const RbfSvmPredictor::Answer& answer = answers[static_cast<std::size_t>(r)];
      differ += answer.label != static_cast<int>(expected.at<float>(r));
      EXPECT_EQ(answer.label, baseline_answers[static_cast<std::size_t>(r)].label);
      EXPECT_EQ(answer.votes, baseline_answers[static_cast<std::size_t>(r)].votes);
      if (r % 100 == 0) {
        // The same float values: a value or a lane out of place changes them (an addition
        // order would only change the doubles' last bits, which the float rarely keeps).
        const std::vector<float> values = predictor->kernelRow(queries.ptr<float>(r));
        const std::vector<float> baseline_values = baseline->kernelRow(queries.ptr<float>(r));
        ASSERT_EQ(values.size(), baseline_values.size());
        for (std::size_t s = 0; s < values.size(); ++s) {
          EXPECT_EQ(values[s], baseline_values[s]) << "support vector " << s;
        }
      }
      wrong += answer.label != unused.at<int>(r);
      // The answer wins at least as many duels as any class, and at most all of its own.
      EXPECT_GE(answer.votes, classes / 2);
      EXPECT_LE(answer.votes, classes - 1);
      unanimous += answer.votes == classes - 1;
    }
    // Near the boundaries, many answers lose a duel; far from them, they win every one.
    EXPECT_GT(unanimous, 0);
    if (classes > 2) {
      EXPECT_LT(unanimous, queries.rows) << classes << " classes";
    }
    EXPECT_EQ(differ, 0) << classes << " classes";
    // The classes overlap: the SVM is often wrong, so the comparison covers boundary cases.
    EXPECT_GT(wrong, 200) << classes << " classes";
  }
}

TEST(RbfSvmPredictorTest, RefusesWhatItDoesNotComputeLikeOpenCv) {
  std::mt19937 random(5);
  cv::Mat samples, responses;
  overlappingClasses(3, 4, 90, random, samples, responses);
  cv::Ptr<cv::ml::SVM> linear = cv::ml::SVM::create();
  linear->setType(cv::ml::SVM::C_SVC);
  linear->setKernel(cv::ml::SVM::LINEAR);
  ASSERT_TRUE(linear->train(samples, cv::ml::ROW_SAMPLE, responses));
  EXPECT_FALSE(RbfSvmPredictor::from(*linear, 3).has_value());

  cv::Ptr<cv::ml::SVM> rbf = cv::ml::SVM::create();
  rbf->setType(cv::ml::SVM::C_SVC);
  rbf->setKernel(cv::ml::SVM::RBF);
  ASSERT_TRUE(rbf->train(samples, cv::ml::ROW_SAMPLE, responses));
  EXPECT_TRUE(RbfSvmPredictor::from(*rbf, 3).has_value());
  // Told of more classes than it was trained on: it has fewer decision functions.
  EXPECT_FALSE(RbfSvmPredictor::from(*rbf, 4).has_value());
  EXPECT_FALSE(RbfSvmPredictor::from(*cv::ml::SVM::create(), 3).has_value());
}

}  // namespace
}  // namespace granular
