// A LiDAR as the box-free path needs to know it: config/sensors/<name>.yaml, or measured from
// its clouds (`sensor:=auto`).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "granular_core/config/fields.h"
#include "granular_core/ground/ground.h"
#include "granular_core/point_types.h"

namespace granular {

/// One sensor file (config/sensors/*.yaml; docs/sensors.md). Every key is required in a file.
struct SensorConfig {
  std::string description = "the simulator's 64-ring LiDAR";
  double mount_height = 2.3;        ///< m, the sensor's origin above the road
  double azimuth_step_deg = 1.0;    ///< deg between consecutive returns along a ring
  int rings = 64;                   ///< lasers
  double min_elevation_deg = -30.665;  ///< deg, lowest ring (negative: below the horizon)
  double max_elevation_deg = 10.665;   ///< deg, highest ring
  double min_range = 0.5;           ///< m
  double max_range = 50.0;          ///< m
  double rate_hz = 10.0;            ///< revolutions per second

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("description", self.description, text("what the sensor is and how it is mounted"));
    visit("mount_height", self.mount_height, positive("m"));
    visit("azimuth_step_deg", self.azimuth_step_deg, interval(0.0, 45.0, "deg", true));
    visit("rings", self.rings, interval(1, 1024, "lasers"));
    visit("min_elevation_deg", self.min_elevation_deg, interval(-90, 90, "deg"));
    visit("max_elevation_deg", self.max_elevation_deg, interval(-90, 90, "deg"));
    visit("min_range", self.min_range, nonNegative("m"));
    visit("max_range", self.max_range, positive("m"));
    visit("rate_hz", self.rate_hz, positive("Hz"));
  }
};

/// Throws std::invalid_argument naming the field for a value out of range, or elevations or
/// ranges out of order.
void validate(const SensorConfig& config);

/// What `sensor:=auto` measured of a sensor from its clouds.
struct SensorEstimate {
  /// m: the median over the clouds of the ground plane's height under the sensor; unset when
  /// no cloud showed ground (`problems` says why).
  std::optional<double> mount_height;
  /// deg: the commonest angle between consecutive returns of one ring (returns grouped by
  /// elevation); unset when the clouds show no ring structure.
  std::optional<double> azimuth_step_deg;
  std::size_t clouds = 0;  ///< clouds looked at
  std::vector<std::string> problems;  ///< why a figure is unset, one line each
};

/// How sensor:=auto measures.
struct SensorEstimateConfig {
  /// m: seeds of the ground plane are looked for below the height of the cloud's lowest
  /// `low_percentile` % of returns plus the ground config's seed_band.
  double low_percentile = 5.0;
  /// deg: returns within this elevation of each other are taken as one ring.
  double elevation_cell_deg = 0.05;
  double min_range = 2.0;   ///< m: nearer returns are the vehicle's own
  double max_range = 60.0;  ///< m
  /// deg: the angle histogram's bins, and the largest angle taken as consecutive returns.
  double step_resolution_deg = 0.002;
  double max_step_deg = 2.0;
  std::size_t min_pairs = 1000;  ///< fewer consecutive pairs: no ring structure to read

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("low_percentile", self.low_percentile, interval(0, 100, "%"));
    visit("elevation_cell_deg", self.elevation_cell_deg, positive("deg"));
    visit("min_range", self.min_range, nonNegative("m"));
    visit("max_range", self.max_range, positive("m"));
    visit("step_resolution_deg", self.step_resolution_deg, positive("deg"));
    visit("max_step_deg", self.max_step_deg, positive("deg"));
    visit("min_pairs", self.min_pairs, atLeast(1, "pairs"));
  }
};

/// Measures a sensor's mounting height (the ground stage's plane, searched without assuming a
/// height) and its azimuth step from `clouds` (sensor frame, z roughly up).
SensorEstimate estimateSensor(const std::vector<Cloud>& clouds, const GroundConfig& ground = {},
                              const SensorEstimateConfig& config = {});

}  // namespace granular
