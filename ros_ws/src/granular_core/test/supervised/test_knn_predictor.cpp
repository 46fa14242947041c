// KnnPredictor against cv::ml::KNearest: the same answer and votes for every query.
#include <random>
#include <stdexcept>
#include <tuple>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "granular_core/supervised/knn_predictor.h"

namespace granular {
namespace {

// Rows of `variables` values on a coarse grid, so that many distances tie exactly, with
// responses 0 .. classes - 1.
void gridSamples(int rows, int variables, int classes, std::mt19937& random, cv::Mat& samples,
                 cv::Mat& responses) {
  std::uniform_int_distribution<int> value(0, 4), label(0, classes - 1);
  samples.create(rows, variables, CV_32F);
  responses.create(rows, 1, CV_32F);
  for (int r = 0; r < rows; ++r) {
    for (int v = 0; v < variables; ++v) {
      samples.at<float>(r, v) = 0.5f * static_cast<float>(value(random));
    }
    responses.at<float>(r) = static_cast<float>(label(random));
  }
}

TEST(KnnPredictorTest, AnswersAndVotesAsOpenCvsFindNearest) {
  std::mt19937 random(7);
  // 6 values: the report's mean and deviation (four at a time, then a tail); 3: tail only.
  for (const auto& [variables, k, training] :
       {std::tuple{6, 3, 500}, std::tuple{3, 5, 300}, std::tuple{6, 4, 3}}) {
    cv::Mat samples, responses;
    gridSamples(training, variables, 4, random, samples, responses);
    cv::Ptr<cv::ml::KNearest> knn = cv::ml::KNearest::create();
    knn->setDefaultK(k);
    knn->setIsClassifier(true);
    ASSERT_TRUE(knn->train(samples, cv::ml::ROW_SAMPLE, responses));
    const KnnPredictor predictor(samples, responses, k);

    cv::Mat queries, unused;
    gridSamples(2000, variables, 4, random, queries, unused);
    cv::Mat expected, neighbours;
    knn->findNearest(queries, k, expected, neighbours);
    const std::vector<KnnPredictor::Answer> answers = predictor.predict(queries);
    ASSERT_EQ(answers.size(), 2000u);
    ASSERT_EQ(predictor.neighbours(), neighbours.cols);  // k, or the 3 of a tiny training set
    int differ = 0, split = 0;
    for (int r = 0; r < queries.rows; ++r) {
      const KnnPredictor::Answer& answer = answers[static_cast<std::size_t>(r)];
      const int votes = cv::countNonZero(neighbours.row(r) == expected.at<float>(r));
      differ += answer.response != expected.at<float>(r) || answer.votes != votes;
      split += votes < neighbours.cols;
    }
    EXPECT_EQ(differ, 0) << variables << " values, k " << k;
    // Split votes and tied distances are common on the grid: the comparison covers them.
    EXPECT_GT(split, 100) << variables << " values, k " << k;
  }
  EXPECT_THROW(KnnPredictor(cv::Mat(), cv::Mat(), 3), std::invalid_argument);
}

}  // namespace
}  // namespace granular
