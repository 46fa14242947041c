// CuboidConfig: defaults, validation naming the field, reading over the defaults.
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/cuboids/cuboid_config.h"

namespace granular {
namespace {

// The message of validate's error for `config`, or "" when it passes.
std::string problem(const CuboidConfig& config) {
  try {
    validate(config);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(CuboidConfigTest, TheDefaultsAreValidAndEveryGeometricClassHasAPrior) {
  const CuboidConfig config;
  EXPECT_EQ(problem(config), "");
  for (const std::string& name : config.geometric.classes) {
    EXPECT_EQ(config.priors.count(name), 1u) << name;
  }
  EXPECT_EQ(config.lshape.criterion, LShapeCriterion::kCloseness);
  EXPECT_EQ(config.lshape.closeness_d0, 0.1);
  EXPECT_EQ(config.priors.at("Car").length, 3.88);
}

TEST(CuboidConfigTest, BadValuesNameTheField) {
  const auto expectProblem = [](const std::function<void(CuboidConfig&)>& change,
                                const std::string& expected) {
    CuboidConfig config;
    change(config);
    const std::string message = problem(config);
    EXPECT_NE(message.find(expected), std::string::npos) << "'" << message << "' lacks '"
                                                         << expected << "'";
  };
  expectProblem([](CuboidConfig& c) { c.lshape.coarse_step_deg = 0.0; }, "lshape.coarse_step_deg");
  expectProblem([](CuboidConfig& c) { c.lshape.fine_step_deg = 2.0; }, "lshape.fine_step_deg");
  expectProblem([](CuboidConfig& c) { c.priors["Car"].width = -1.0; }, "priors.Car.width");
  expectProblem([](CuboidConfig& c) { c.priors["Car"].length = 1e30; }, "priors.Car.length");
  // Steps and bins that would take the fit hours or all memory.
  expectProblem([](CuboidConfig& c) { c.lshape.fine_step_deg = 1e-9; }, "lshape.fine_step_deg");
  expectProblem([](CuboidConfig& c) { c.free_space.bin_deg = 1e-9; }, "free_space.bin_deg");
  expectProblem([](CuboidConfig& c) { c.free_space.occupied_cell = 1e-9; },
                "free_space.occupied_cell");
  expectProblem([](CuboidConfig& c) { c.free_space.occupied_cell = 0.01; },
                "free_space.occupied_range");
  expectProblem([](CuboidConfig& c) { c.split.search_step_deg = 1e-9; }, "split.search_step_deg");
  expectProblem([](CuboidConfig& c) { c.free_space.step = 1e-9; }, "free_space.step");
  // Not "got null", JSON's word for it.
  expectProblem([](CuboidConfig& c) { c.lshape.cell = std::nan(""); }, "got nan");
  expectProblem([](CuboidConfig& c) { c.geometric.classes = {"Tram"}; }, "'Tram'");
  expectProblem([](CuboidConfig& c) { c.geometric.classes = {""}; }, "geometric.classes[0]");
  expectProblem([](CuboidConfig& c) { c.points.min_height = 5.0; }, "points.min_height");
  expectProblem([](CuboidConfig& c) { c.points.min_points = 2; }, "points.min_points");
  expectProblem([](CuboidConfig& c) { c.model.headings = 3; }, "model.headings");
  expectProblem([](CuboidConfig& c) { c.model.voxel = 0.0; }, "model.voxel");
  expectProblem([](CuboidConfig& c) { c.model.registration.icp.max_iterations = 0; },
                "model.registration.icp.max_iterations");
}

TEST(CuboidConfigTest, ReadingLaysKeysOverTheDefaults) {
  CuboidConfig config;
  config::readJson(config::Json::parse(R"({"method": "geometric",
      "lshape": {"criterion": "variance"},
      "priors": {"Car": {"length": 4.2}, "Tram": {"length": 30, "width": 2.6, "height": 3.5}},
      "geometric": {"classes": ["Car", "Tram"]}})"),
                   config);
  EXPECT_EQ(problem(config), "");
  EXPECT_EQ(config.method, CuboidMethod::kGeometric);
  EXPECT_EQ(config.lshape.criterion, LShapeCriterion::kVariance);
  EXPECT_EQ(config.priors.at("Car").length, 4.2);
  EXPECT_EQ(config.priors.at("Car").width, 1.63);  // kept
  EXPECT_EQ(config.priors.at("Tram").length, 30.0);
  EXPECT_EQ(config.priors.size(), defaultSizePriors().size() + 1);
  // Written and read back, the same config.
  CuboidConfig again;
  config::readJson(config::toJson(config), again);
  EXPECT_TRUE(again == config);
}

TEST(CuboidConfigTest, UnknownKeysAreRefused) {
  CuboidConfig config;
  EXPECT_THROW(config::readJson(config::Json::parse(R"({"lshape": {"critrion": "area"}})"), config),
               config::FieldError);
  EXPECT_THROW(config::readJson(config::Json::parse(R"({"lshape": {"criterion": "mean"}})"), config),
               config::FieldError);
}

}  // namespace
}  // namespace granular
