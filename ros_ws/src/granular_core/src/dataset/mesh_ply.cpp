#include "granular_core/dataset/mesh_ply.h"

#include <pcl/io/ply_io.h>

#include "granular_core/dataset/atomic_file.h"

namespace granular {

void writeMeshPly(const std::filesystem::path& file, const pcl::PolygonMesh& mesh) {
  writeThroughTemporary(file, "PLY", [&](const std::filesystem::path& partial) {
    return pcl::io::savePLYFileBinary(partial.string(), mesh) == 0;
  });
}

}  // namespace granular
