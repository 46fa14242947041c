#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "granular_core/point_types.h"

namespace granular {

/// A class model: its label and its cloud in the object frame.
struct LabelledModel {
  std::string label;
  ModelCloud cloud;
};

/// m and share: a cloud in a box-centre frame has more than kBoxCentredShare of its points
/// below kBoxCentredDepth.
inline constexpr double kBoxCentredDepth = -0.1;
inline constexpr double kBoxCentredShare = 0.1;

/// Points of `cloud` below the height `z` (m).
std::size_t pointsBelow(const ModelCloud& cloud, double z);

/// True when `cloud` looks as if it were in a box-centre frame (z = 0 at half the box's
/// height) instead of the object frame (z = 0 on the road, the object in z >= 0): more than
/// 10% of its points lie below z = -0.1 m. Ground returns and sensor noise stay well above.
bool looksBoxCentred(const ModelCloud& cloud);

/// The class models of a models folder: every `<Class>.pcd` at its top level (as build_models
/// writes them; its raw/ and mesh/ subfolders and hidden files are ignored), in label order.
/// Throws std::runtime_error naming the folder or file when it is not a folder, holds no
/// PCD, a PCD cannot be read or is empty, or a model looks box-centred (looksBoxCentred).
std::vector<LabelledModel> readClassModels(const std::filesystem::path& folder);

}  // namespace granular
