#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace granular {

/// One row of an objects folder's index.csv: an object file and the detection it came from.
struct ObjectIndexRow {
  std::string file;     ///< object file name in the folder
  std::string label;    ///< the label as given (index.csv is its source of truth)
  std::string detection_id;
  std::string stamp;
  std::size_t points = 0;
  double range = 0.0;   ///< m, of the box centre from the sensor
  double length = 0.0;  ///< m, of the detection box
  double width = 0.0;   ///< m
  double height = 0.0;  ///< m
  double yaw = 0.0;     ///< rad
};

/// index.csv's first line.
const char* objectIndexHeader();

/// One line of index.csv (RFC 4180 quoting where a field needs it), newline included.
std::string objectIndexLine(const ObjectIndexRow& row);

/// The rows of `folder`/index.csv; none when the folder has no index.csv (a hand-made objects
/// folder). Throws std::runtime_error naming the file and line for a line that does not parse.
std::vector<ObjectIndexRow> readObjectIndex(const std::filesystem::path& folder);

}  // namespace granular
