#include "granular_core/models/mesh.h"

#include <cmath>
#include <stdexcept>

#include <pcl/common/io.h>
#include <pcl/features/normal_3d.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>


namespace granular {
namespace {

double radians(double degrees) { return degrees * M_PI / 180.0; }

}  // namespace

pcl::PolygonMesh triangulate(const ModelCloud& model, const MeshConfig& config) {
  pcl::PolygonMesh mesh;
  if (model.size() < 3) {
    return mesh;
  }
  const ModelCloud::ConstPtr points(new ModelCloud(model));
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(points);
  estimation.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(
      new pcl::search::KdTree<pcl::PointXYZ>));
  estimation.setKSearch(config.normal_k);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);

  pcl::PointCloud<pcl::PointNormal>::Ptr oriented(new pcl::PointCloud<pcl::PointNormal>);
  pcl::concatenateFields(model, normals, *oriented);

  pcl::search::KdTree<pcl::PointNormal>::Ptr tree(new pcl::search::KdTree<pcl::PointNormal>);
  tree->setInputCloud(oriented);
  pcl::GreedyProjectionTriangulation<pcl::PointNormal> triangulation;
  triangulation.setSearchRadius(config.search_radius);
  triangulation.setMu(config.mu);
  triangulation.setMaximumNearestNeighbors(config.max_nearest_neighbors);
  triangulation.setMaximumSurfaceAngle(radians(config.max_surface_angle_deg));
  triangulation.setMinimumAngle(radians(config.min_angle_deg));
  triangulation.setMaximumAngle(radians(config.max_angle_deg));
  triangulation.setNormalConsistency(false);
  triangulation.setInputCloud(oriented);
  triangulation.setSearchMethod(tree);
  triangulation.reconstruct(mesh);
  return mesh;
}

}  // namespace granular
