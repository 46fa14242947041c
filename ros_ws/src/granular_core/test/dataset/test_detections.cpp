// Detections JSON as bag to files writes it.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/dataset/detections.h"
#include "support/detections_json.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_support::detectionJson;
using testing_support::frameJson;
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

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
  EXPECT_EQ(detection.velocity, Eigen::Vector3d(9.6, 0, 0));
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

TEST_F(DetectionsJsonTest, WrittenDetectionsReadBackExactly) {
  Detection box;
  box.id = 7;
  box.label = "Tram_/_Subway";
  box.centre = {12.345678901234567, -0.1, -1.0 / 3.0};
  box.orientation = Eigen::Quaterniond(0.9, 0.1, -0.2, 0.3);
  box.size = {4.5, 1.8, 1.0 / 7.0};
  box.score = 0.25;
  box.velocity = {3.5, -0.25, 1.0 / 3.0};
  const DetectionsHeader header{1586102742, 765440, "velodyne"};
  const fs::path file = write("written.json", detectionsJson({box, Detection()}, header));
  DetectionsHeader read_header;
  const std::vector<Detection> read = readDetectionsJson(file, &read_header);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].id, 7);
  EXPECT_EQ(read[0].label, "Tram_/_Subway");
  EXPECT_EQ(read[0].centre, box.centre);
  EXPECT_EQ(read[0].orientation.coeffs(), box.orientation.coeffs());
  EXPECT_EQ(read[0].size, box.size);
  EXPECT_EQ(read[0].score, 0.25);
  EXPECT_EQ(read[1].score, 1.0);
  EXPECT_EQ(read[0].velocity, box.velocity);
  EXPECT_EQ(read[1].velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(read_header.secs, 1586102742);
  EXPECT_EQ(read_header.nsecs, 765440);
  EXPECT_EQ(read_header.frame_id, "velodyne");
  // An empty list is a frame without detections.
  EXPECT_TRUE(readDetectionsJson(write("empty.json", detectionsJson({}, header))).empty());
}

TEST_F(DetectionsJsonTest, AHeaderIsReadWhereThereIsOne) {
  DetectionsHeader header{1, 2, "kept"};
  readDetectionsJson(write("bare.json", R"({"detections": []})"), &header);
  EXPECT_EQ(header.secs, 1);
  EXPECT_EQ(header.frame_id, "kept");
  readDetectionsJson(write("full.json", frameJson("")), &header);
  EXPECT_EQ(header.secs, 1586102742);
  EXPECT_EQ(header.nsecs, 765440);
  EXPECT_EQ(header.frame_id, "velodyne");
}

}  // namespace
}  // namespace granular
