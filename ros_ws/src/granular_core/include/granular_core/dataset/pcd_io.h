#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "granular_core/point_types.h"

namespace granular {

/// Reads a PCD file (ascii, binary or binary_compressed) as an unorganised cloud. x, y and z must
/// be float32 fields; intensity (uint8) and timestamp (float64) are read when present and are 0
/// when absent. Throws std::runtime_error naming the file when it cannot be read, has no x/y/z
/// fields, or has a known field of another type.
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

}  // namespace granular
