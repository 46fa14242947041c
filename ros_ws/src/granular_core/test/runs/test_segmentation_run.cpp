// evaluateSegmentation: the box-free path scored against true boxes, with the segments' own
// boxes or with the cuboids fitted to them.
#include <filesystem>
#include <memory>
#include <sstream>

#include <gtest/gtest.h>

#include "granular_core/dataset/pcd_io.h"
#include "granular_core/runs/segmentation_run.h"
#include "support/detections_json.h"
#include "support/road_scene.h"
#include "support/temporary_folder.h"
#include "support/visible_faces.h"

namespace granular {
namespace {
using testing_support::detectionJson;
using testing_support::frameJson;
using testing_support::kSensorHeight;
using testing_support::road;
using testing_support::seenFaces;
using testing_support::StandingBox;
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

// One frame: a road 1.73 m below the sensor and a 4.5 x 1.8 x 1.5 m car 12 m straight ahead,
// seen from behind (its rear face only), with its true box.
class EvaluateSegmentationTest : public TemporaryFolderTest {
 protected:
  void SetUp() override {
    TemporaryFolderTest::SetUp();
    frames_ = root_ / "frames";
    const std::string stamp = "1586102742000765440";
    StandingBox car;
    car.centre = {12.0, 0.0};
    Cloud cloud = road();
    for (const Eigen::Vector3d& p :
         seenFaces(car, Eigen::Vector3d(0, 0, kSensorHeight), 0.05)) {
      cloud.push_back(PointXYZIT(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                 static_cast<float>(p.z() - kSensorHeight), 0, 0.0));
    }
    fs::create_directories(frames_ / "pcd");
    writePcdBinary(frames_ / "pcd" / (stamp + ".pcd"), cloud);
    write(frames_ / "detections_3d" / (stamp + ".json"),
          frameJson(detectionJson(7, "Car", R"({"x": 12.0, "y": 0.0, "z": -0.98})",
                                  R"({"x": 4.5, "y": 1.8, "z": 1.5})")));
  }

  fs::path frames_;
};

TEST_F(EvaluateSegmentationTest, ARearFacesBoxMissesTheCarAndItsCuboidFindsIt) {
  const GroundConfig ground;
  const SegmentationStageConfig config;
  // The segment's box encloses the rear face, 2.25 m before the car's centre.
  const SegmentationEvaluation boxes = evaluateSegmentation(frames_, ground, config);
  EXPECT_EQ(boxes.visible, 1u);
  EXPECT_EQ(boxes.segments, 1u);
  EXPECT_EQ(boxes.found, 0u);
  EXPECT_EQ(boxes.false_segments, 1u);
  // The cuboid grows the rear away from the sensor to the car's length.
  CuboidConfig cuboids;
  cuboids.priors = {{"Car", {4.5, 1.8, 1.5}}};
  cuboids.geometric.classes = {"Car"};
  const std::unique_ptr<CuboidFitter> fitter = makeCuboidFitter(cuboids, {});
  SegmentationEvaluationOptions options;
  options.cuboids = fitter.get();
  options.free_space = cuboids.free_space;
  const SegmentationEvaluation fitted = evaluateSegmentation(frames_, ground, config, options);
  EXPECT_EQ(fitted.segments, 1u);
  EXPECT_EQ(fitted.found, 1u);
  EXPECT_EQ(fitted.footprint, 1u);
  EXPECT_EQ(fitted.false_segments, 0u);
}

TEST_F(EvaluateSegmentationTest, ATrueBoxThatIsNoBoxIsSkippedAndNamed) {
  // Beside the car's box, one of negative size: before, the whole run failed on it, unnamed.
  const fs::path json = frames_ / "detections_3d" / "1586102742000765440.json";
  write(json, frameJson(detectionJson(7, "Car", R"({"x": 12.0, "y": 0.0, "z": -0.98})",
                                      R"({"x": 4.5, "y": 1.8, "z": 1.5})") +
                        ", " +
                        detectionJson(8, "Car", R"({"x": 20.0, "y": 5.0, "z": -0.98})",
                                      R"({"x": -4.5, "y": 1.8, "z": 1.5})")));
  const SegmentationEvaluation evaluation =
      evaluateSegmentation(frames_, GroundConfig(), SegmentationStageConfig());
  EXPECT_EQ(evaluation.visible, 1u);
  ASSERT_EQ(evaluation.invalid_truth.size(), 1u);
  EXPECT_NE(evaluation.invalid_truth[0].find(json.string() + ": detections[1] (id 8, Car): "),
            std::string::npos)
      << evaluation.invalid_truth[0];
}

TEST_F(EvaluateSegmentationTest, CloudsWithoutTruthAreCountedAndTheReportWarns) {
  for (const fs::directory_entry& entry : fs::directory_iterator(frames_ / "detections_3d")) {
    fs::remove(entry.path());
  }
  const SegmentationEvaluation evaluation =
      evaluateSegmentation(frames_, GroundConfig(), SegmentationStageConfig());
  EXPECT_EQ(evaluation.frames_without_truth, 1u);
  EXPECT_EQ(evaluation.visible, 0u);
  std::ostringstream report;
  evaluation.report(report);
  EXPECT_NE(report.str().find("warning: 1 of the 1 clouds have no detections_3d"),
            std::string::npos)
      << report.str();
}

}  // namespace
}  // namespace granular
