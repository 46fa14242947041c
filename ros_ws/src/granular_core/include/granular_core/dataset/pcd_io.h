#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "granular_core/point_types.h"

namespace granular {

/// Reads a PCD file (ascii, binary or binary_compressed) as an unorganised cloud, whatever the
/// sensor's layout (the simulator's, velodyne_pointcloud's x y z intensity ring time, an
/// Ouster's): x, y and z must be float32 or float64 fields; intensity, of any numeric type, is
/// rounded and clamped to 0-255; timestamp (or else time), of any numeric type, is read as
/// seconds; both are 0 when absent, and other fields are ignored. Throws std::runtime_error
/// naming the file when it cannot be read, has no x/y/z fields, or has a known field that
/// holds several values.
Cloud readPcd(const std::filesystem::path& file);

/// The header of a binary, unorganised PCD file of `points` points whose FIELDS, SIZE, TYPE and
/// COUNT lines carry the given values (e.g. "x y z", "4 4 4", "F F F", "1 1 1").
std::string binaryPcdHeader(const std::string& fields, const std::string& sizes,
                            const std::string& types, const std::string& counts,
                            std::size_t points);

/// Writes `cloud` as binary PCD, checking every write (writeFile: a failure removes the file
/// and throws std::runtime_error naming it). For files inside an OutputFolder's staging folder,
/// which is put in place as a whole.
void writePcdBinary(const std::filesystem::path& file, const Cloud& cloud);

/// The finite points of `cloud`, x y z only; `dropped`, when given, receives how many were not
/// finite.
ModelCloud toModelCloud(const Cloud& cloud, std::size_t* dropped = nullptr);

/// Reads any PCD with float x, y and z fields (readPcd) as a model cloud, without its
/// non-finite points. Throws std::runtime_error naming the file.
ModelCloud readModelPcd(const std::filesystem::path& file);

/// Writes `cloud` as binary PCD with the fields `x y z`, checking every write (writeFile), for
/// a staging folder. Throws std::runtime_error naming the file on failure.
void writeModelPcd(const std::filesystem::path& file, const ModelCloud& cloud);

}  // namespace granular
