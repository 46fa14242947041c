// PCD files: our layout, ASCII, real sensors' layouts, bad files.
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/model_clouds.h"

#include "granular_core/dataset/pcd_io.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_clouds::pointsOf;
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

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

TEST(ConcatenateTest, ModelCloudDropsNonFinitePoints) {
  Cloud cloud;
  cloud.push_back(PointXYZIT(1, 2, 3, 7, 0.5));
  cloud.push_back(PointXYZIT(NAN, 2, 3, 7, 0.5));
  cloud.push_back(PointXYZIT(4, 5, INFINITY, 7, 0.5));
  std::size_t dropped = 0;
  const ModelCloud model = toModelCloud(cloud, &dropped);
  EXPECT_EQ(dropped, 2u);
  EXPECT_EQ(pointsOf(model), std::vector<Eigen::Vector3f>({{1, 2, 3}}));
}

}  // namespace
}  // namespace granular
