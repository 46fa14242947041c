#pragma once

#include <pcl/PolygonMesh.h>

#include "granular_core/point_types.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// A triangle mesh of a model (report section 6, an alternative representation no classifier
/// uses): normals estimated from the config.normal_k nearest neighbours, then
/// pcl::GreedyProjectionTriangulation. The mesh's vertices are the model's points, with their
/// normals. An empty model gives an empty mesh.
pcl::PolygonMesh triangulate(const ModelCloud& model, const MeshConfig& config);

}  // namespace granular
