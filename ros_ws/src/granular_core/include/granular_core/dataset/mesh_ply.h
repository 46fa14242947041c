#pragma once

#include <filesystem>

#include <pcl/PolygonMesh.h>

namespace granular {

/// Writes `mesh` as binary PLY under a temporary name renamed to `file` at the end. Throws
/// std::runtime_error naming the file on failure.
void writeMeshPly(const std::filesystem::path& file, const pcl::PolygonMesh& mesh);

}  // namespace granular
