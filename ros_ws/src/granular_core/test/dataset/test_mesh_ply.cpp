// A class model's mesh as binary PLY: what is written reads back, and a failed write leaves
// nothing.
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <pcl/conversions.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include "granular_core/dataset/mesh_ply.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

using MeshPlyTest = TemporaryFolderTest;

// One triangle in the object frame.
pcl::PolygonMesh triangle() {
  pcl::PointCloud<pcl::PointXYZ> vertices;
  vertices.push_back(pcl::PointXYZ(0.0f, 0.0f, 0.0f));
  vertices.push_back(pcl::PointXYZ(4.5f, 0.0f, 0.25f));
  vertices.push_back(pcl::PointXYZ(0.0f, 1.75f, 1.5f));
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2(vertices, mesh.cloud);
  pcl::Vertices face;
  face.vertices = {0, 1, 2};
  mesh.polygons.push_back(face);
  return mesh;
}

TEST_F(MeshPlyTest, WhatIsWrittenReadsBackTheSame) {
  const fs::path file = root_ / "Sedan.ply";
  writeMeshPly(file, triangle());
  pcl::PolygonMesh read;
  ASSERT_EQ(pcl::io::loadPLYFile(file.string(), read), 0);
  pcl::PointCloud<pcl::PointXYZ> vertices;
  pcl::fromPCLPointCloud2(read.cloud, vertices);
  ASSERT_EQ(vertices.size(), 3u);
  EXPECT_EQ(vertices[1].x, 4.5f);
  EXPECT_EQ(vertices[1].z, 0.25f);
  EXPECT_EQ(vertices[2].y, 1.75f);
  ASSERT_EQ(read.polygons.size(), 1u);
  EXPECT_EQ(read.polygons[0].vertices, (std::vector<pcl::index_t>{0, 1, 2}));
}

TEST_F(MeshPlyTest, AFailedWriteNamesTheFileAndLeavesNothing) {
  const fs::path file = root_ / "missing" / "Sedan.ply";
  try {
    writeMeshPly(file, triangle());
    FAIL() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()).rfind(file.string() + ": cannot write PLY", 0), 0u)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(root_ / "missing"));
}

}  // namespace
}  // namespace granular
