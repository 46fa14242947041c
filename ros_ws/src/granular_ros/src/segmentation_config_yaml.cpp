#include "granular_ros/segmentation_config_yaml.h"

#include "granular_ros/yaml_reader.h"

namespace granular_ros {

void loadSegmentationConfig(const std::filesystem::path& file,
                            granular::SegmentationConfig& config) {
  const YamlReader reader(file);
  reader.forEachKey("", reader.load(),
                    {{"cell_size", reader.set(config.cell_size)},
                     {"extent", reader.set(config.extent)},
                     {"height_threshold", reader.set(config.height_threshold)},
                     {"link_cells", reader.set(config.link_cells)},
                     {"min_cells", reader.set(config.min_cells)},
                     {"min_points", reader.set(config.min_points)},
                     {"max_length", reader.set(config.max_length)}});
}

}  // namespace granular_ros
