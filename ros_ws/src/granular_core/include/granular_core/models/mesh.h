#pragma once

#include <filesystem>

#include <pcl/PolygonMesh.h>

#include "granular_core/models/model_cloud.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// A triangle mesh of a model (report section 6, an alternative representation no classifier
/// uses): normals estimated from the config.normal_k nearest neighbours, then
/// pcl::GreedyProjectionTriangulation. The mesh's vertices are the model's points, with their
/// normals. An empty model gives an empty mesh.
pcl::PolygonMesh triangulate(const ModelCloud& model, const MeshConfig& config);

/// Writes `mesh` as binary PLY under a temporary name renamed to `file` at the end. Throws
/// std::runtime_error naming the file on failure.
void writeMeshPly(const std::filesystem::path& file, const pcl::PolygonMesh& mesh);

}  // namespace granular
