// Heights above per-sector ground lines (Himmelsbach, Hundelshausen and Wuensche 2010).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "granular_core/geometry/fast_atan2.h"
#include "granular_core/ground/ground.h"

namespace granular {
namespace {

// The lowest point of one range bin of a sector: its range and z.
struct BinPoint {
  double range;
  double z;
};

// A line z = slope * r + intercept fitted to points by least squares, grown one point at a time.
class LineFit {
 public:
  void add(const BinPoint& p) {
    ++n_;
    sr_ += p.range;
    sz_ += p.z;
    srr_ += p.range * p.range;
    srz_ += p.range * p.z;
    szz_ += p.z * p.z;
  }
  std::size_t size() const { return n_; }
  // A single point is flat.
  double slope() const {
    const double denominator = n_ * srr_ - sr_ * sr_;
    return n_ < 2 || denominator <= 0.0 ? 0.0 : (n_ * srz_ - sr_ * sz_) / denominator;
  }
  double intercept() const { return n_ == 0 ? 0.0 : (sz_ - slope() * sr_) / n_; }
  double at(double range) const { return slope() * range + intercept(); }
  // Root mean square distance (in z) of the points from the line.
  double rmse() const {
    if (n_ < 3) {
      return 0.0;
    }
    const double m = slope(), c = intercept();
    // sum (z - m r - c)^2, expanded over the sums.
    const double sse = szz_ - 2 * m * srz_ - 2 * c * sz_ + m * m * srr_ + 2 * m * c * sr_ +
                       c * c * static_cast<double>(n_);
    return std::sqrt(std::max(0.0, sse) / static_cast<double>(n_));
  }

 private:
  std::size_t n_ = 0;
  double sr_ = 0, sz_ = 0, srr_ = 0, srz_ = 0, szz_ = 0;
};

// A ground line of a sector, from the range of its first point.
struct GroundLine {
  double start;
  double end;
  double slope;
  double intercept;
};

// The ground lines of one sector from its bins' lowest points (by increasing range).
std::vector<GroundLine> sectorGroundLines(const std::vector<BinPoint>& bins,
                                          const GroundLinesConfig& config,
                                          const GroundPlane& plane, double azimuth) {
  // The lines, each a run of consecutive bins.
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // [first, last]
  LineFit current;
  std::size_t first = 0;
  for (std::size_t j = 0; j < bins.size(); ++j) {
    if (current.size() == 0) {
      current.add(bins[j]);
      first = j;
      continue;
    }
    const double predicted = current.size() >= 2 ? current.at(bins[j].range) : current.intercept();
    LineFit trial = current;
    trial.add(bins[j]);
    if (std::abs(bins[j].z - predicted) <= config.max_step && trial.rmse() <= config.max_rmse &&
        (trial.size() < 3 || std::abs(trial.slope()) <= config.max_slope)) {
      current = trial;
    } else {
      runs.emplace_back(first, j - 1);
      current = LineFit();
      current.add(bins[j]);
      first = j;
    }
  }
  if (current.size() > 0) {
    runs.emplace_back(first, bins.size() - 1);
  }

  // The plane's z along this sector's middle, at range r.
  const double c = std::cos(azimuth), s = std::sin(azimuth);
  const auto plane_z = [&](double r) {
    return -(plane.normal.x() * r * c + plane.normal.y() * r * s + plane.offset) /
           plane.normal.z();
  };
  std::vector<GroundLine> ground;
  for (const auto& [from, to] : runs) {
    LineFit fit;
    for (std::size_t j = from; j <= to; ++j) {
      fit.add(bins[j]);
    }
    double slope = fit.slope();
    if (fit.size() == 1) {
      slope = ground.empty() ? 0.0 : ground.back().slope;
    }
    const double intercept =
        fit.size() == 1 ? bins[from].z - slope * bins[from].range : fit.intercept();
    if (std::abs(slope) > config.max_slope) {
      continue;
    }
    const double start = bins[from].range;
    const double start_z = slope * start + intercept;
    const bool continues =
        ground.empty()
            ? std::abs(start_z - plane_z(start)) <=
                  config.first_line_tolerance + config.first_line_tolerance_per_m * start
            : std::abs(start_z - (ground.back().slope * start + ground.back().intercept)) <=
                  config.max_step + 0.02 * (start - ground.back().end);
    if (continues) {
      ground.push_back({start, bins[to].range, slope, intercept});
    }
  }
  return ground;
}

}  // namespace

std::vector<float> groundLineHeights(const Cloud& cloud, const GroundPlane& plane,
                                     const GroundLinesConfig& config) {
  const int sectors = config.sectors;
  const auto bins_per_sector = static_cast<std::size_t>(std::ceil(config.max_range / config.bin_size));
  const double sector_width = 2.0 * M_PI / sectors;
  std::vector<float> heights(cloud.size(), std::numeric_limits<float>::quiet_NaN());
  std::vector<int> sector_of(cloud.size(), -1);
  std::vector<double> range_of(cloud.size(), 0.0);
  // The lowest z per (sector, bin); NaN for an empty bin.
  std::vector<double> lowest(static_cast<std::size_t>(sectors) * bins_per_sector,
                             std::numeric_limits<double>::quiet_NaN());
  std::vector<double> lowest_range(lowest.size(), 0.0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointXYZIT& point = cloud[i];
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) {
      continue;
    }
    heights[i] = static_cast<float>(plane.heightOf(Eigen::Vector3d(point.x, point.y, point.z)));
    const double range = std::sqrt(double(point.x) * point.x + double(point.y) * point.y);
    if (range >= config.max_range) {
      continue;
    }
    const double azimuth = fastAtan2(point.y, point.x) + M_PI;
    const int sector = std::min(sectors - 1, static_cast<int>(azimuth / sector_width));
    sector_of[i] = sector;
    range_of[i] = range;
    const std::size_t bin = std::min(bins_per_sector - 1,
                                     static_cast<std::size_t>(range / config.bin_size));
    const std::size_t cell = static_cast<std::size_t>(sector) * bins_per_sector + bin;
    if (!(lowest[cell] <= point.z)) {  // NaN compares false: an empty bin takes the point
      lowest[cell] = point.z;
      lowest_range[cell] = range;
    }
  }

  std::vector<std::vector<GroundLine>> lines(static_cast<std::size_t>(sectors));
  std::vector<BinPoint> bins;
  for (int sector = 0; sector < sectors; ++sector) {
    bins.clear();
    for (std::size_t bin = 0; bin < bins_per_sector; ++bin) {
      const std::size_t cell = static_cast<std::size_t>(sector) * bins_per_sector + bin;
      if (!std::isnan(lowest[cell])) {
        bins.push_back({lowest_range[cell], lowest[cell]});
      }
    }
    if (!bins.empty()) {
      const double middle = (sector + 0.5) * sector_width - M_PI;
      lines[static_cast<std::size_t>(sector)] = sectorGroundLines(bins, config, plane, middle);
    }
  }

  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (sector_of[i] < 0) {
      continue;
    }
    const std::vector<GroundLine>& ground = lines[static_cast<std::size_t>(sector_of[i])];
    if (ground.empty()) {
      continue;  // the plane's height
    }
    // The last ground line starting at or before the point's range, else the first.
    auto line = std::upper_bound(ground.begin(), ground.end(), range_of[i],
                                 [](double r, const GroundLine& l) { return r < l.start; });
    if (line != ground.begin()) {
      --line;
    }
    heights[i] = static_cast<float>(cloud[i].z - (line->slope * range_of[i] + line->intercept));
  }
  return heights;
}

}  // namespace granular
