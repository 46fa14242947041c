#include "granular_core/registration/registration.h"

#include <algorithm>
#include <string>

namespace granular {
namespace {

constexpr RegistrationState kStates[] = {
    RegistrationState::kTransform,  RegistrationState::kAbsMse,
    RegistrationState::kRelMse,     RegistrationState::kIterations,
    RegistrationState::kNoCorrespondences, RegistrationState::kFailed,
    RegistrationState::kTooFewPoints};

// Whether `point` is at or above source_min_z, when set.
bool aboveMinZ(const pcl::PointXYZ& point, const RegistrationClassifierConfig& config) {
  return !config.source_min_z || point.z >= *config.source_min_z;
}

// How many of `count` points source_max_points keeps.
std::size_t keptCount(std::size_t count, const RegistrationClassifierConfig& config) {
  return config.source_max_points == 0 ? count : std::min(count, config.source_max_points);
}

}  // namespace

const char* registrationStateName(RegistrationState state) {
  switch (state) {
    case RegistrationState::kTransform:
      return "transform";
    case RegistrationState::kAbsMse:
      return "abs_mse";
    case RegistrationState::kRelMse:
      return "rel_mse";
    case RegistrationState::kIterations:
      return "iterations";
    case RegistrationState::kNoCorrespondences:
      return "no_correspondences";
    case RegistrationState::kFailed:
      return "failed";
    case RegistrationState::kTooFewPoints:
      return "too_few_points";
  }
  return "unknown";
}

std::optional<RegistrationState> registrationStateFromName(const std::string& name) {
  for (const RegistrationState state : kStates) {
    if (name == registrationStateName(state)) {
      return state;
    }
  }
  return std::nullopt;
}

bool isConverged(RegistrationState state) {
  return state == RegistrationState::kTransform || state == RegistrationState::kAbsMse ||
         state == RegistrationState::kRelMse;
}

std::size_t minimumSourcePoints(RegistrationMethod method) {
  return method == RegistrationMethod::kIcpNl ? 4 : 3;
}

nlohmann::json registrationParameters(RegistrationMethod method,
                                      const RegistrationClassifierConfig& config) {
  // The config's own JSON keeps the fields' order; re-read, the keys are sorted.
  nlohmann::json json = nlohmann::json::parse(
      (method == RegistrationMethod::kNdt ? config::toJson(config.ndt)
       : method == RegistrationMethod::kIcp ? config::toJson(config.icp)
                                            : config::toJson(config.icp_nl))
          .dump());
  json["source_min_z"] =
      config.source_min_z ? nlohmann::json(*config.source_min_z) : nlohmann::json(nullptr);
  json["source_max_points"] = config.source_max_points;
  json["min_source_points"] = minimumSourcePoints(method);
  return json;
}

ModelCloud::ConstPtr registrationSource(const ModelCloud& object,
                                        const RegistrationClassifierConfig& config) {
  ModelCloud::Ptr source(new ModelCloud);
  if (!config.source_min_z) {
    *source = object;
  } else {
    source->reserve(object.size());
    for (const pcl::PointXYZ& point : object.points) {
      if (aboveMinZ(point, config)) {
        source->push_back(point);
      }
    }
  }
  const std::size_t count = source->size();
  const std::size_t kept = keptCount(count, config);
  if (kept == count) {
    return source;
  }
  // Point i of the kept ones is point floor(i * count / kept) of the source: evenly spread
  // over a scan's order, which sweeps the object's surface ring by ring.
  ModelCloud::Ptr spread(new ModelCloud);
  spread->reserve(kept);
  for (std::size_t i = 0; i < kept; ++i) {
    spread->push_back((*source)[i * count / kept]);
  }
  return spread;
}

std::size_t registrationSourceSize(const ModelCloud& object,
                                   const RegistrationClassifierConfig& config) {
  const auto above = std::count_if(object.begin(), object.end(), [&](const pcl::PointXYZ& point) {
    return aboveMinZ(point, config);
  });
  return keptCount(static_cast<std::size_t>(above), config);
}

PairResult failedPair() {
  PairResult result;
  result.state = RegistrationState::kFailed;
  return result;
}

}  // namespace granular
