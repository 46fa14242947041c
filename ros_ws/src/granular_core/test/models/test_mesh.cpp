// Triangle meshes of models.
#include <random>

#include <gtest/gtest.h>

#include "granular_core/models/mesh.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::lattice;

TEST(MeshTest, TriangulatesASurfaceAndToleratesTinyModels) {
  const ModelCloud plane = lattice({0, 0, 1}, 0.05, 20, 20, 1);
  const pcl::PolygonMesh mesh = triangulate(plane, MeshConfig());
  EXPECT_EQ(mesh.cloud.width * mesh.cloud.height, 400u);
  EXPECT_GT(mesh.polygons.size(), 300u);  // a full triangulation of the grid has 722
  EXPECT_TRUE(triangulate(ModelCloud(), MeshConfig()).polygons.empty());
}

}  // namespace
}  // namespace granular
