// extractFolder: objects folders from a frames folder.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "granular_core/dataset/output_folder.h"
#include "granular_core/dataset/objects_index.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/runs/extract_run.h"
#include "support/detections_json.h"
#include "support/road_scene.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_support::detectionJson;
using testing_support::frameJson;
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

// One bag-to-files frame: a Sedan box holding 120 points and an SUV box holding 20.
class ExtractFolderTest : public TemporaryFolderTest {
 protected:
  const std::string stamp_ = "1586102742000765440";

  void SetUp() override {
    TemporaryFolderTest::SetUp();
    in_ = root_ / "in";
    Cloud cloud;
    for (int i = 0; i < 120; ++i) {
      cloud.push_back(PointXYZIT(10.0f + 0.01f * i, 0.0f, -1.0f, 1, i));
    }
    for (int i = 0; i < 20; ++i) {
      cloud.push_back(PointXYZIT(-5.0f, 3.0f + 0.01f * i, -1.0f, 2, i));
    }
    cloud.push_back(PointXYZIT(50.0f, 50.0f, 0.0f, 3, 0.0));
    fs::create_directories(in_ / "pcd");
    writePcdBinary(in_ / "pcd" / (stamp_ + ".pcd"), cloud);
    write(in_ / "detections_3d" / (stamp_ + ".json"),
          frameJson(detectionJson(136, "Sedan", R"({"x": 10.6, "y": 0.0, "z": -1.0})",
                                  R"({"x": 4.0, "y": 2.0, "z": 1.5})") +
                    "," +
                    detectionJson(9, "SUV", R"({"x": -5.0, "y": 3.0, "z": -1.0})",
                                  R"({"x": 4.0, "y": 2.0, "z": 1.5})")));
    writePcdBinary(in_ / "pcd" / "1586102743000000000.pcd", cloud);
    write(in_ / "detections_3d" / "1586102744000000000.json", frameJson(""));
  }

  fs::path in_;
};

TEST_F(ExtractFolderTest, SeveralThresholdsInOnePass) {
  ExtractionConfig config;
  config.n_thresh = {300, 10, 100, 50};
  const fs::path out = root_ / "objects";
  const ExtractFolderSummary summary = extractFolder(in_, out, config);

  EXPECT_EQ(summary.frames_read, 1u);
  ASSERT_EQ(summary.frames_skipped.size(), 2u);
  EXPECT_EQ(summary.frames_skipped[0],
            "1586102743000000000: no detections_3d/1586102743000000000.json");
  EXPECT_EQ(summary.frames_skipped[1], "1586102744000000000: no pcd/1586102744000000000.pcd");
  EXPECT_TRUE(summary.invalid_detections.empty());

  const std::string sedan = "Sedan-" + stamp_ + "-1.pcd";
  const std::string suv = "SUV-" + stamp_ + "-1.pcd";
  const std::string header =
      "file,label,detection_id,stamp,points,range_m,length_m,width_m,height_m,yaw_rad\n";
  const std::string sedan_row = sedan + ",Sedan,136," + stamp_ +
                                ",120,10.6471,4.0000,2.0000,1.5000,0.000000\n";
  const std::string suv_row =
      suv + ",SUV,9," + stamp_ + ",20,5.9161,4.0000,2.0000,1.5000,0.000000\n";

  EXPECT_EQ(read(out / "N10" / "index.csv"), header + sedan_row + suv_row);
  EXPECT_EQ(read(out / "N50" / "index.csv"), header + sedan_row);
  EXPECT_EQ(read(out / "N100" / "index.csv"), header + sedan_row);
  EXPECT_EQ(read(out / "N300" / "index.csv"), header);
  EXPECT_TRUE(fs::exists(out / "N10" / suv));
  EXPECT_FALSE(fs::exists(out / "N50" / suv));
  EXPECT_FALSE(fs::exists(out / "N300" / sedan));
  EXPECT_EQ(fs::hard_link_count(out / "N100" / sedan), 3u);
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "N300"), fs::directory_iterator()), 1);

  const Cloud object = readPcd(out / "N50" / sedan);
  ASSERT_EQ(object.size(), 120u);
  EXPECT_NEAR(object[0].x, -0.6, 1e-4);
  EXPECT_NEAR(object[0].z, 0.75, 1e-4);
  EXPECT_EQ(summary.objects.at(10).at("SUV"), 1u);
  EXPECT_EQ(summary.objects.at(100).at("Sedan"), 1u);
  EXPECT_TRUE(summary.objects.at(300).empty());
  EXPECT_EQ(summary.objects.size(), 4u);
  // Nothing but the result is left beside it.
  EXPECT_EQ(std::distance(fs::directory_iterator(root_), fs::directory_iterator()), 2);
}

TEST_F(ExtractFolderTest, OneThresholdWritesIntoTheOutputFolder) {
  ExtractionConfig config;
  config.n_thresh = {50};
  config.labels = {"Sedan", "SUV"};
  const fs::path out = root_ / "objects";
  extractFolder(in_, out, config);
  EXPECT_TRUE(fs::exists(out / ("Sedan-" + stamp_ + "-1.pcd")));
  EXPECT_FALSE(fs::exists(out / ("SUV-" + stamp_ + "-1.pcd")));
  EXPECT_TRUE(fs::exists(out / "index.csv"));
  EXPECT_FALSE(fs::exists(out / "N50"));
}

TEST_F(ExtractFolderTest, BoxesFromAnotherFolderReplaceTheFramesOwn) {
  // fit_cuboids' output for a bag without boxes: one unknown box on the Sedan's points, and
  // the tool's manifest, which is no frame.
  const fs::path boxes = root_ / "cuboids";
  write(boxes / (stamp_ + ".json"),
        frameJson(detectionJson(0, "unknown", R"({"x": 10.6, "y": 0.0, "z": -1.0})",
                                R"({"x": 4.0, "y": 2.0, "z": 1.5})")));
  write(boxes / ".granular.json", R"({"tool": "fit_cuboids"})");
  ExtractionConfig config;
  config.n_thresh = {10};
  ExtractFolderOptions options;
  options.boxes = boxes;
  const ExtractFolderSummary summary = extractFolder(in_, root_ / "objects", config, options);
  EXPECT_EQ(summary.frames_read, 1u);
  ASSERT_EQ(summary.frames_skipped.size(), 1u);
  EXPECT_EQ(summary.frames_skipped[0], "1586102743000000000: no " +
                                           (boxes / "1586102743000000000.json").string());
  EXPECT_EQ(readPcd(root_ / "objects" / ("unknown-" + stamp_ + "-1.pcd")).size(), 120u);
  EXPECT_EQ(summary.objects.at(10).size(), 1u);
}

// A bag-to-files folder `in` of one frame `kStamp`: a road with a car 10 m ahead, 4 x 1.8 m,
// labelled Sedan with a box centred `box_x` m ahead of size `box_size` (JSON), and an
// unlabelled hedge 8 m to the left. The car's and the hedge's points.
constexpr const char* kStamp = "1586102742000000000";
std::pair<std::set<std::size_t>, std::set<std::size_t>> writeCarAndHedge(
    const fs::path& in, double box_x, const std::string& box_size) {
  Cloud cloud = testing_support::road();
  std::set<std::size_t> car = testing_support::addBox(cloud, {10.0, 0.0}, 0.0, {4.0, 1.8, 1.5});
  std::set<std::size_t> hedge = testing_support::addBox(cloud, {0.0, 8.0}, 0.3, {3.0, 1.0, 1.2});
  fs::create_directories(in / "pcd");
  writePcdBinary(in / "pcd" / (std::string(kStamp) + ".pcd"), cloud);
  const double bottom = -testing_support::kSensorHeight;
  fs::create_directories(in / "detections_3d");
  std::ofstream(in / "detections_3d" / (std::string(kStamp) + ".json"))
      << frameJson(detectionJson(7, "Sedan",
                                 R"({"x": )" + std::to_string(box_x) + R"(, "y": 0.0, "z": )" +
                                     std::to_string(bottom + 0.75) + "}",
                                 box_size));
  return {std::move(car), std::move(hedge)};
}

// Points of `cloud` above its object frame's bottom (the road under a box is at 0).
std::ptrdiff_t pointsAboveTheBottom(const Cloud& cloud) {
  return std::count_if(cloud.begin(), cloud.end(),
                       [](const PointXYZIT& point) { return point.z > 0.1f; });
}

TEST_F(TemporaryFolderTest, BackgroundIsHarvestedFromTheSegmentsOnNoTrueBox) {
  const fs::path in = root_ / "frames";
  const auto [car, hedge] = writeCarAndHedge(in, 10.0, R"({"x": 4.0, "y": 1.8, "z": 1.5})");
  const std::string stamp = kStamp;
  ExtractionConfig config;
  config.n_thresh = {10};
  config.labels = {"Sedan"};  // the filter keeps the harvest
  ExtractFolderOptions options;
  options.background = BackgroundHarvest{testing_support::roadGround(), {}};
  const ExtractFolderSummary summary = extractFolder(in, root_ / "objects", config, options);
  EXPECT_EQ(summary.objects.at(10).at("Sedan"), 1u);
  EXPECT_EQ(summary.objects.at(10).at("Background"), 1u);
  EXPECT_EQ(readPcd(root_ / "objects" / ("Sedan-" + stamp + "-1.pcd")).size(), car.size());
  // The hedge's points, and the road under its segment's box (from the ground up).
  const Cloud background = readPcd(root_ / "objects" / ("Background-" + stamp + "-1.pcd"));
  EXPECT_EQ(pointsAboveTheBottom(background), static_cast<std::ptrdiff_t>(hedge.size()));
  EXPECT_TRUE(summary.warnings.empty());
}

TEST_F(TemporaryFolderTest, ABoxThatCannotBeJudgedOnGivesNoBackgroundFromItsFrame) {
  // The car labelled with a 1e30 m box: taken as it was, every segment lay on it and became a
  // Sedan; left out silently, the car became Background. Neither is training data.
  const fs::path in = root_ / "frames";
  writeCarAndHedge(in, 10.0, R"({"x": 1e30, "y": 1.8, "z": 1.5})");
  ExtractionConfig config;
  config.n_thresh = {10};
  for (const bool segment_objects : {false, true}) {
    ExtractFolderOptions options;
    options.output.overwrite = true;
    options.background = BackgroundHarvest{testing_support::roadGround(), {}, segment_objects};
    const ExtractFolderSummary summary = extractFolder(in, root_ / "objects", config, options);
    EXPECT_TRUE(summary.objects.empty() || summary.objects.at(10).empty())
        << "segment_objects " << segment_objects;
    ASSERT_EQ(summary.invalid_detections.size(), 1u);
    EXPECT_NE(summary.invalid_detections[0].find("max_box_size"), std::string::npos)
        << summary.invalid_detections[0];
  }
}

TEST_F(TemporaryFolderTest, SegmentObjectsAreTheSegmentsOnTheTrueBoxes) {
  // The car labelled with a loose box, 6 x 3 m and 0.5 m too far.
  const fs::path in = root_ / "frames";
  const std::set<std::size_t> car =
      writeCarAndHedge(in, 10.5, R"({"x": 6.0, "y": 3.0, "z": 1.5})").first;
  const std::string stamp = kStamp;
  ExtractionConfig config;
  config.n_thresh = {10};
  // The centre of the Sedan object's points in its own frame.
  const auto centre = [&](bool segment_objects) {
    ExtractFolderOptions options;
    options.output.overwrite = true;
    options.background = BackgroundHarvest{testing_support::roadGround(), {}, segment_objects};
    const ExtractFolderSummary summary = extractFolder(in, root_ / "objects", config, options);
    EXPECT_EQ(summary.objects.at(10).at("Sedan"), 1u);
    EXPECT_EQ(summary.objects.at(10).at("Background"), 1u);
    const Cloud sedan = readPcd(root_ / "objects" / ("Sedan-" + stamp + "-1.pcd"));
    EXPECT_EQ(pointsAboveTheBottom(sedan), static_cast<std::ptrdiff_t>(car.size()));
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (const PointXYZIT& point : sedan) {
      sum += Eigen::Vector2d(point.x, point.y);
    }
    return Eigen::Vector2d(sum / static_cast<double>(sedan.size()));
  };
  // In its segment's box the car is centred; in the loose box it sits 0.5 m back.
  EXPECT_LT(centre(true).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT(centre(false).x(), -0.4);
  // Either way the object is the labelled car, instance 7, for scores over instances.
  for (const bool segment_objects : {true, false}) {
    centre(segment_objects);
    bool found = false;
    for (const ObjectIndexRow& row : readObjectIndex(root_ / "objects")) {
      if (row.label == "Sedan") {
        EXPECT_EQ(row.detection_id, "7") << "segment_objects " << segment_objects;
        found = true;
      }
    }
    EXPECT_TRUE(found);
  }
}

TEST_F(ExtractFolderTest, NeverReplacesAFolderOfOtherFilesEvenWithOverwrite) {
  const fs::path out = root_ / "objects";
  write(out / "keep.txt", "mine");
  ExtractFolderOptions options;
  options.output.overwrite = true;
  try {
    extractFolder(in_, out, ExtractionConfig(), options);
    FAIL() << "a folder of the user's files was replaced";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(out.string() + ": output folder holds files that "
                                             "no granular tool wrote"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(read(out / "keep.txt"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
}

TEST_F(ExtractFolderTest, ReplacesItsOwnResultsOnlyWithOverwrite) {
  const fs::path out = root_ / "objects";
  extractFolder(in_, out, ExtractionConfig());
  EXPECT_TRUE(fs::exists(out / kManifestName));
  EXPECT_NE(read(out / kManifestName).find(R"("tool": "extract_objects")"), std::string::npos);
  try {
    extractFolder(in_, out, ExtractionConfig());
    FAIL() << "an earlier result was replaced without overwrite";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("holds results of extract_objects; pass "
                                             "--overwrite to replace them"),
              std::string::npos)
        << error.what();
  }

  ExtractFolderOptions options;
  options.output.overwrite = true;
  std::size_t progress_calls = 0;
  options.progress = [&](std::size_t done, std::size_t total) {
    ++progress_calls;
    EXPECT_EQ(done, 1u);
    EXPECT_EQ(total, 1u);
  };
  extractFolder(in_, out, ExtractionConfig(), options);
  EXPECT_EQ(progress_calls, 1u);
  EXPECT_TRUE(fs::exists(out / "index.csv"));
  // Beside the input only the output: no staging or set-aside folder.
  std::set<std::string> entries;
  for (const fs::directory_entry& entry : fs::directory_iterator(root_)) {
    entries.insert(entry.path().filename().string());
  }
  EXPECT_EQ(entries, (std::set<std::string>{"in", "objects"}));
}

TEST_F(ExtractFolderTest, AFailureLeavesNoOutput) {
  write(in_ / "pcd" / "1586102745000000000.pcd", "not a point cloud\n");
  write(in_ / "detections_3d" / "1586102745000000000.json", frameJson(""));
  const fs::path out = root_ / "objects";
  try {
    extractFolder(in_, out, ExtractionConfig());
    FAIL() << "a broken PCD was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("1586102745000000000.pcd"), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(std::distance(fs::directory_iterator(root_), fs::directory_iterator()), 1);
}

TEST_F(ExtractFolderTest, RejectsAFolderThatIsNotBagToFiles) {
  EXPECT_THROW(extractFolder(root_ / "nowhere", root_ / "objects", ExtractionConfig()),
               std::runtime_error);
  ExtractionConfig config;
  config.n_thresh = {0};
  EXPECT_THROW(extractFolder(in_, root_ / "objects", config), std::invalid_argument);
  fs::create_directories(root_ / "empty" / "pcd");
  fs::create_directories(root_ / "empty" / "detections_3d");
  EXPECT_THROW(extractFolder(root_ / "empty", root_ / "objects", ExtractionConfig()),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(root_ / "objects"));
}

}  // namespace
}  // namespace granular
