#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/dataset/output_folder.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/extraction/detections.h"
#include "granular_core/extraction/extract_folder.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

// A fresh folder under the system temporary folder, removed with the fixture.
class TemporaryFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    root_ = fs::temp_directory_path() /
            ("granular_core_test_" + std::to_string(entropy()) + std::to_string(entropy()));
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path write(const fs::path& relative, const std::string& content) const {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << content;
    return path;
  }

  static std::string read(const fs::path& path) {
    std::ifstream stream(path);
    std::stringstream content;
    content << stream.rdbuf();
    return content.str();
  }

  fs::path root_;
};

std::string detectionJson(int id, const std::string& label, const std::string& position,
                          const std::string& size) {
  return R"({"header": {"stamp": {"secs": 0, "nsecs": 0}, "frame_id": "", "seq": 0}, "id": )" +
         std::to_string(id) + R"(, "label": ")" + label +
         R"(", "score": 1.0, "bbox": {"position": {"position": )" + position +
         R"(, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}, "size": )" + size +
         R"(}, "velocity": {"linear": {"x": 0, "y": 0, "z": 0},)"
         R"( "angular": {"x": 0, "y": 0, "z": 0}}})";
}

std::string frameJson(const std::string& detections) {
  return R"({"header": {"stamp": {"secs": 1586102742, "nsecs": 765440}, "frame_id": "velodyne",)"
         R"( "seq": 375}, "detections": [)" +
         detections + "]}";
}

using DetectionsJsonTest = TemporaryFolderTest;

TEST_F(DetectionsJsonTest, ReadsTheBagToFilesLayout) {
  const fs::path file = write(
      "a.json",
      frameJson(R"({"header": {"stamp": {"secs": 1586102742, "nsecs": 765440},
            "frame_id": "velodyne", "seq": 375},
 "id": 136, "label": "Sedan", "score": 1.0,
 "bbox": {"position": {"position": {"x": -10.9, "y": 0.76, "z": -1.98},
                       "orientation": {"x": 0.0014, "y": 0.00026, "z": 0.0053, "w": -0.99998}},
          "size": {"x": 4.56, "y": 2.08, "z": 1.35}},
 "velocity": {"linear": {"x": 9.6, "y": 0, "z": 0}, "angular": {"x": 0, "y": 0, "z": 0.23}}})"));
  const std::vector<Detection> detections = readDetectionsJson(file);
  ASSERT_EQ(detections.size(), 1u);
  const Detection& detection = detections[0];
  EXPECT_EQ(detection.id, 136);
  EXPECT_EQ(detection.label, "Sedan");
  EXPECT_EQ(detection.centre, Eigen::Vector3d(-10.9, 0.76, -1.98));
  EXPECT_EQ(detection.orientation.x(), 0.0014);
  EXPECT_EQ(detection.orientation.y(), 0.00026);
  EXPECT_EQ(detection.orientation.z(), 0.0053);
  EXPECT_EQ(detection.orientation.w(), -0.99998);
  EXPECT_EQ(detection.size, Eigen::Vector3d(4.56, 2.08, 1.35));
}

void expectErrorMentions(const fs::path& file, const std::vector<std::string>& parts) {
  try {
    readDetectionsJson(file);
    FAIL() << file << " was accepted";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << message << " lacks " << part;
    }
  }
}

TEST_F(DetectionsJsonTest, ErrorsNameTheFileAndTheKey) {
  const std::string position = R"({"x": 1, "y": 2, "z": 3})";
  const std::string size = R"({"x": 4, "y": 2, "z": 1.5})";
  const std::string whole = frameJson(detectionJson(1, "Sedan", position, size));
  expectErrorMentions(write("truncated.json", whole.substr(0, 80)), {"not valid JSON"});
  expectErrorMentions(write("no_detections.json", R"({"header": {}})"),
                      {"detections", "missing key"});
  expectErrorMentions(write("no_size_z.json",
                            frameJson(detectionJson(1, "Sedan", position, size) + "," +
                                      detectionJson(2, "SUV", position, R"({"x": 4, "y": 2})"))),
                      {"detections[1].bbox.size.z", "missing key"});
  std::string number_label = frameJson(detectionJson(1, "Sedan", position, size));
  number_label.replace(number_label.find(R"("Sedan")"), 7, "5");
  expectErrorMentions(write("number_label.json", number_label),
                      {"detections[0].label", "expected a string, got number"});
  const std::string string_x =
      frameJson(detectionJson(1, "Sedan", R"({"x": "1", "y": 2, "z": 3})", size));
  expectErrorMentions(write("string_x.json", string_x),
                      {"detections[0].bbox.position.position.x", "expected a number, got string"});
  expectErrorMentions(root_ / "absent.json", {"cannot open"});
}

using PcdIoTest = TemporaryFolderTest;

TEST_F(PcdIoTest, WritesBinaryWithTheBagToFilesFieldsAndReadsItBack) {
  Cloud cloud;
  cloud.push_back(PointXYZIT(1.5f, -2.25f, 3.0f, 200, 1586102742.123456789));
  cloud.push_back(PointXYZIT(-0.5f, 0.0f, -2.3f, 7, 1586102742.2));
  const fs::path file = root_ / "cloud.pcd";
  writePcdBinary(file, cloud);

  const std::string content = read(file);
  EXPECT_NE(content.find("FIELDS x y z intensity timestamp\nSIZE 4 4 4 1 8\nTYPE F F F U F\n"),
            std::string::npos)
      << content.substr(0, 300);
  EXPECT_NE(content.find("DATA binary\n"), std::string::npos);
  EXPECT_EQ(std::distance(fs::directory_iterator(root_), fs::directory_iterator()), 1)
      << "the temporary file was left behind";

  const Cloud back = readPcd(file);
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].x, cloud[i].x);
    EXPECT_EQ(back[i].y, cloud[i].y);
    EXPECT_EQ(back[i].z, cloud[i].z);
    EXPECT_EQ(back[i].intensity, cloud[i].intensity);
    EXPECT_EQ(back[i].timestamp, cloud[i].timestamp);
  }
}

TEST_F(PcdIoTest, ReadsAscii) {
  const fs::path file = write("ascii.pcd",
                              "VERSION 0.7\nFIELDS x y z intensity timestamp\nSIZE 4 4 4 1 8\n"
                              "TYPE F F F U F\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
                              "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
                              "1 2 3 255 10.5\n-4 5.5 -6 0 11.25\n");
  const Cloud cloud = readPcd(file);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud[1].x, -4.0f);
  EXPECT_EQ(cloud[1].y, 5.5f);
  EXPECT_EQ(cloud[0].intensity, 255);
  EXPECT_EQ(cloud[1].timestamp, 11.25);
}

// velodyne_pointcloud's layout (float32 intensity, uint16 ring, float32 time) and an Ouster's
// (uint16 intensity): the values every stage reads come through; other fields are ignored.
TEST_F(PcdIoTest, ReadsTheLayoutsOfRealSensors) {
  const std::string header_end = "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n";
  const Cloud velodyne = readPcd(
      write("velodyne.pcd", "VERSION 0.7\nFIELDS x y z intensity ring time\nSIZE 4 4 4 4 2 4\n"
                            "TYPE F F F F U F\nCOUNT 1 1 1 1 1 1\n" + header_end +
                                "1.5 -2 0.25 37.4 12 0.0125\n3 4 5 300 63 0.05\n"));
  ASSERT_EQ(velodyne.size(), 2u);
  EXPECT_EQ(velodyne[0].x, 1.5f);
  EXPECT_EQ(velodyne[0].y, -2.0f);
  EXPECT_EQ(velodyne[0].z, 0.25f);
  EXPECT_EQ(velodyne[0].intensity, 37);
  EXPECT_EQ(velodyne[1].intensity, 255) << "brighter than 255 saturates";
  EXPECT_DOUBLE_EQ(velodyne[0].timestamp, static_cast<double>(0.0125f));
  const Cloud ouster =
      readPcd(write("ouster.pcd", "VERSION 0.7\nFIELDS x y z intensity reflectivity\n"
                                  "SIZE 8 8 8 2 2\nTYPE F F F U U\nCOUNT 1 1 1 1 1\n" +
                                      header_end + "1 2 3 12 7\n4 5 6 1000 9\n"));
  ASSERT_EQ(ouster.size(), 2u);
  EXPECT_EQ(ouster[1].z, 6.0f);
  EXPECT_EQ(ouster[0].intensity, 12);
  EXPECT_EQ(ouster[0].timestamp, 0.0);
}

TEST_F(PcdIoTest, RejectsCloudsWithoutXyzOrWithWrongTypes) {
  const std::string header_end =
      "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n";
  const fs::path no_z = write("no_z.pcd", "VERSION 0.7\nFIELDS x y intensity\nSIZE 4 4 1\n"
                                          "TYPE F F U\nCOUNT 1 1 1\n" + header_end + "1 2 3\n");
  try {
    readPcd(no_z);
    FAIL() << "a cloud without z was accepted";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(no_z.string()), std::string::npos) << message;
    EXPECT_NE(message.find("'z'"), std::string::npos) << message;
  }
  const fs::path two_intensities =
      write("two_intensities.pcd", "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\n"
                                   "TYPE F F F F\nCOUNT 1 1 1 2\n" + header_end + "1 2 3 0.5 1\n");
  EXPECT_THROW(readPcd(two_intensities), std::runtime_error);
  const fs::path integer_x =
      write("integer_x.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE I F F\n"
                             "COUNT 1 1 1\n" + header_end + "1 2 3\n");
  EXPECT_THROW(readPcd(integer_x), std::runtime_error);
  EXPECT_THROW(readPcd(write("garbage.pcd", "not a point cloud\n")), std::runtime_error);
  EXPECT_THROW(readPcd(root_ / "absent.pcd"), std::runtime_error);
}

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
