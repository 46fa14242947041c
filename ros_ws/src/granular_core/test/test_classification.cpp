#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/common/transforms.h>
#include <nlohmann/json.hpp>

#include "granular_core/classification/classify_folder.h"
#include "granular_core/classification/nearest_grid.h"
#include "granular_core/classification/nearest_points.h"
#include "granular_core/classification/object_classifier.h"
#include "granular_core/classification/registration_classifier.h"
#include "granular_core/models/model_cloud.h"
#include "model_clouds.h"

namespace granular {
namespace {

namespace fs = std::filesystem;
using testing_clouds::boxSurface;
using testing_clouds::shifted;

PairResult pair(RegistrationState state, double fitness) {
  PairResult result;
  result.state = state;
  result.fitness = fitness;
  return result;
}

TEST(CriteriaTest, FollowTheReportsThreeRules) {
  const auto converged = RegistrationState::kTransform;
  const auto iterations = RegistrationState::kIterations;
  // Converged to exactly one model (index 1): all three criteria may differ.
  Predictions one = predict({pair(iterations, 0.01), pair(converged, 0.05), pair(iterations, 0.2)});
  EXPECT_EQ(one.criterion1, 1u);
  EXPECT_EQ(one.criterion2, 1u);
  EXPECT_EQ(one.criterion3, 0u);
  // Converged to two: no criterion 1; criterion 2 takes the lower fitness of those two.
  Predictions two = predict({pair(converged, 0.05), pair(iterations, 0.01),
                             pair(RegistrationState::kRelMse, 0.03)});
  EXPECT_FALSE(two.criterion1);
  EXPECT_EQ(two.criterion2, 2u);
  EXPECT_EQ(two.criterion3, 1u);
  // Converged to none: only criterion 3.
  Predictions none = predict({pair(iterations, 0.05), pair(RegistrationState::kNoCorrespondences, 0.04)});
  EXPECT_FALSE(none.criterion1);
  EXPECT_FALSE(none.criterion2);
  EXPECT_EQ(none.criterion3, 1u);
  // Registrations that did not run have no fitness and predict nothing.
  Predictions small = predict({PairResult(), PairResult()});
  EXPECT_FALSE(small.criterion1 || small.criterion2 || small.criterion3);
}

TEST(ConvergenceTest, ReachingTheIterationLimitIsNotConvergence) {
  for (const char* name : {"transform", "abs_mse", "rel_mse"}) {
    EXPECT_TRUE(isConverged(*registrationStateFromName(name))) << name;
  }
  for (const char* name : {"iterations", "no_correspondences", "failed", "too_few_points"}) {
    EXPECT_FALSE(isConverged(*registrationStateFromName(name))) << name;
  }
}

// Two clearly different class models in the object frame, and partial views of each.
class RegistrationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(5);
    models_.push_back({"Long", boxSurface({4.6, 1.8, 1.4}, 4000, random)});
    models_.push_back({"Tall", boxSurface({2.0, 1.6, 2.6}, 4000, random)});
    for (int i = 0; i < 6; ++i) {
      // A view of the left side and the front, a few centimetres off, as extraction gives.
      const Eigen::Vector3f offset(0.02f * (i % 3), -0.015f * (i % 2), 0.0f);
      for (std::size_t m = 0; m < models_.size(); ++m) {
        ModelCloud view;
        for (const pcl::PointXYZ& p : models_[m].cloud.points) {
          if ((p.y > 0.5f || p.x > 0.8f) && view.size() < 300) {
            view.push_back(p);
          }
        }
        objects_.push_back(shifted(view, offset));
        truth_.push_back(m);
      }
    }
  }

  static RegistrationClassifierConfig converging() {
    RegistrationClassifierConfig config;
    config.icp.max_iterations = 30;
    config.icp.max_correspondence_distance = 0.1;
    config.icp_nl = config.icp;
    config.ndt.resolution = 0.5;
    return config;
  }

  std::vector<LabelledModel> models_;
  std::vector<ModelCloud> objects_;
  std::vector<std::size_t> truth_;
};

TEST_F(RegistrationTest, EveryMethodTellsTheShapesApart) {
  for (const RegistrationMethod method :
       {RegistrationMethod::kIcp, RegistrationMethod::kIcpNl, RegistrationMethod::kNdt}) {
    const RegistrationClassifier classifier(method, converging(), models_);
    const auto results = classifier.registerObjects(objects_);
    ASSERT_EQ(results.size(), objects_.size());
    for (std::size_t i = 0; i < objects_.size(); ++i) {
      const Predictions predictions = predict(results[i]);
      EXPECT_EQ(predictions.criterion3, truth_[i])
          << registrationMethodName(method) << " object " << i;
      EXPECT_EQ(predictions.criterion2, truth_[i])
          << registrationMethodName(method) << " object " << i;
      EXPECT_TRUE(results[i][truth_[i]].converged())
          << registrationMethodName(method) << " object " << i << ": "
          << registrationStateName(results[i][truth_[i]].state);
    }
  }
}

TEST_F(RegistrationTest, IcpRecoversTheOffsetOfAView) {
  const RegistrationClassifier classifier(RegistrationMethod::kIcp, converging(), models_);
  const ModelCloud view = shifted(models_[0].cloud, Eigen::Vector3f(0.04f, -0.03f, 0.0f));
  const PairResult result = classifier.registerObjects({view})[0][0];
  ASSERT_TRUE(result.converged()) << registrationStateName(result.state);
  EXPECT_NEAR(result.transform(0, 3), -0.04, 0.01);
  EXPECT_NEAR(result.transform(1, 3), 0.03, 0.01);
  EXPECT_LT(result.fitness, 1e-4);
}

TEST_F(RegistrationTest, TheReportsSingleIterationNeverConverges) {
  // PCL's hasConverged() is true here; the convergence state says the limit stopped it.
  const RegistrationClassifier classifier(RegistrationMethod::kIcp,
                                          RegistrationClassifierConfig(), models_);
  const auto results = classifier.registerObjects(objects_);
  for (const auto& per_model : results) {
    for (const PairResult& result : per_model) {
      EXPECT_FALSE(result.converged()) << registrationStateName(result.state);
      EXPECT_EQ(result.iterations, result.state == RegistrationState::kIterations ? 1 : 0);
    }
  }
}

TEST_F(RegistrationTest, CachedAndThreadedResultsEqualTheReportsLoop) {
  // The views, and the same views turned about z by a few degrees, which NDT and ICP take
  // several steps (and NDT's line search several trials) to undo.
  std::vector<ModelCloud> objects = objects_;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    ModelCloud turned;
    const Eigen::Affine3f turn(Eigen::AngleAxisf(0.03f * static_cast<float>(i % 4 + 1),
                                                 Eigen::Vector3f::UnitZ()));
    pcl::transformPointCloud(objects_[i], turned, turn);
    objects.push_back(turned);
  }
  int several_steps = 0;
  RegistrationClassifierConfig fine_ndt = converging();
  fine_ndt.ndt.resolution = 0.2;
  fine_ndt.ndt.transformation_epsilon = 1e-4;
  for (const RegistrationMethod method :
       {RegistrationMethod::kIcp, RegistrationMethod::kIcpNl, RegistrationMethod::kNdt}) {
    for (const RegistrationClassifierConfig& config :
         {RegistrationClassifierConfig(), converging(), fine_ndt}) {
      if (method != RegistrationMethod::kNdt && config == fine_ndt) {
        continue;
      }
      const RegistrationClassifier classifier(method, config, models_);
      RegisterOptions options;
      options.threads = 2;
      const auto fast = classifier.registerObjects(objects, options);
      const auto plain = classifier.registerObjectsPlain(objects);
      for (std::size_t i = 0; i < objects.size(); ++i) {
        for (std::size_t m = 0; m < models_.size(); ++m) {
          EXPECT_EQ(fast[i][m].state, plain[i][m].state) << i << " " << m;
          EXPECT_EQ(fast[i][m].iterations, plain[i][m].iterations) << i << " " << m;
          // Bit for bit: the same nearest distances, summed in the same order.
          EXPECT_EQ(fast[i][m].fitness, plain[i][m].fitness)
              << registrationMethodName(method) << " object " << i << " model " << m;
          EXPECT_TRUE(fast[i][m].transform == plain[i][m].transform) << i << " " << m;
          several_steps += fast[i][m].iterations > 2 ? 1 : 0;
        }
      }
    }
  }
  EXPECT_GT(several_steps, 10);  // the comparison covers long alignments, not just one step
}

TEST_F(RegistrationTest, ObjectsTooSmallAreRecordedNotRegistered) {
  ModelCloud two;
  two.push_back(pcl::PointXYZ(1.0f, 0.9f, 0.5f));
  two.push_back(pcl::PointXYZ(1.1f, 0.9f, 0.5f));
  for (const RegistrationMethod method :
       {RegistrationMethod::kIcp, RegistrationMethod::kIcpNl, RegistrationMethod::kNdt}) {
    const RegistrationClassifier classifier(method, converging(), models_);
    const auto results = classifier.registerObjects({two, ModelCloud()});
    for (const auto& per_model : results) {
      for (const PairResult& result : per_model) {
        EXPECT_EQ(result.state, RegistrationState::kTooFewPoints);
        EXPECT_TRUE(std::isinf(result.fitness));
      }
      EXPECT_FALSE(predict(per_model).criterion3);
    }
  }
}

TEST_F(RegistrationTest, SourceMinZDropsGroundReturns) {
  RegistrationClassifierConfig config = converging();
  config.source_min_z = 0.2;
  ModelCloud view = objects_[0];
  for (int i = 0; i < 200; ++i) {  // road returns far from any model point
    view.push_back(pcl::PointXYZ(-3.0f + 0.03f * i, 3.0f, 0.02f));
  }
  const RegistrationClassifier with(RegistrationMethod::kIcp, config, models_);
  const RegistrationClassifier without(RegistrationMethod::kIcp, converging(), models_);
  const PairResult kept = without.registerObjects({view})[0][0];
  const PairResult dropped = with.registerObjects({view})[0][0];
  EXPECT_GT(kept.fitness, 1.0);     // the road points are metres from the model
  EXPECT_LT(dropped.fitness, 1e-3);
}

TEST(ClassifierConfigTest, RefusesBadInput) {
  RegistrationClassifierConfig config;
  config.ndt.resolution = 0.0;
  EXPECT_THROW(validate(config), std::invalid_argument);
  std::mt19937 random(1);
  const LabelledModel model{"A", boxSurface({1, 1, 1}, 100, random)};
  EXPECT_THROW(RegistrationClassifier(RegistrationMethod::kIcp, {}, {}), std::invalid_argument);
  EXPECT_THROW(RegistrationClassifier(RegistrationMethod::kIcp, {}, {model, model}),
               std::invalid_argument);
  EXPECT_THROW(RegistrationClassifier(RegistrationMethod::kIcp, {}, {{"B", ModelCloud()}}),
               std::invalid_argument);
}

// The points as x y z floats, as NearestGrid and NearestPoints take them.
std::vector<float> xyzOf(const ModelCloud& cloud) {
  std::vector<float> xyz;
  for (const pcl::PointXYZ& p : cloud.points) {
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
  }
  return xyz;
}

// Brute force with FLANN's L2_Simple order of operations.
float bruteNearest(const std::vector<float>& points, const float* query, float bound) {
  float best = bound;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    float d = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
      const float step = query[axis] - points[3 * i + axis];
      d += step * step;
    }
    best = std::min(best, d);
  }
  return best;
}

TEST(NearestSearchTest, GridAndTreeFindTheExactNearestDistance) {
  std::mt19937 random(7);
  const ModelCloud surface = boxSurface({4.5, 1.8, 1.5}, 3000, random);
  const std::vector<float> points = xyzOf(surface);
  const NearestGrid grid(points.data(), surface.size(), 2);
  const NearestPoints tree(points.data(), surface.size());
  std::uniform_real_distribution<float> near(-3.0f, 3.0f);
  std::uniform_real_distribution<float> far(-20.0f, 20.0f);
  int resolved = 0;
  for (int i = 0; i < 4000; ++i) {
    auto& distribution = i % 4 == 0 ? far : near;
    const float query[3] = {distribution(random), distribution(random), distribution(random)};
    for (const float bound : {std::numeric_limits<float>::infinity(), 0.01f, 0.5f}) {
      const float expected = bruteNearest(points, query, bound);
      const NearestPoints::Result exact = tree.nearest(query, bound);
      EXPECT_EQ(exact.found, expected < bound);
      EXPECT_EQ(exact.distance, expected);  // bit for bit
      if (exact.found) {
        const float* p = &points[3 * exact.index];
        EXPECT_EQ(bruteNearest({p[0], p[1], p[2]}, query, bound), expected);
      }
      const NearestGrid::Result cell = grid.nearest(query, bound);
      if (cell.resolved) {
        ++resolved;
        EXPECT_EQ(cell.found, expected < bound);
        EXPECT_EQ(cell.distance, expected);
      } else {
        EXPECT_GE(cell.distance, expected);  // the best seen is an upper bound
      }
    }
  }
  EXPECT_GT(resolved, 2000);  // the grid settles most queries near the cloud
}

TEST(NearestSearchTest, APacketOfQueriesGetsEachQuerysExactDistance) {
  std::mt19937 random(11);
  const ModelCloud surface = boxSurface({4.5, 1.8, 1.5}, 3000, random);
  const std::vector<float> points = xyzOf(surface);
  const NearestPoints tree(points.data(), surface.size());
  constexpr int kPacket = NearestPoints::kPacket;
  std::uniform_real_distribution<float> centre(-12.0f, 12.0f);
  std::uniform_real_distribution<float> spread(-0.3f, 0.3f);
  for (int packet = 0; packet < 500; ++packet) {
    // Neighbouring queries, as a scan gives, and now and then one from elsewhere.
    const float around[3] = {centre(random), centre(random), centre(random) / 4.0f};
    float queries[kPacket][3];
    float bounds[kPacket];
    for (int lane = 0; lane < kPacket; ++lane) {
      for (int axis = 0; axis < 3; ++axis) {
        queries[lane][axis] = lane == 3 && packet % 5 == 0 ? centre(random)
                                                           : around[axis] + spread(random);
      }
      const float choices[] = {std::numeric_limits<float>::infinity(), 0.01f, 4.0f, 60.0f};
      bounds[lane] = choices[(packet + lane) % 4];
    }
    float distances[kPacket];
    tree.nearestDistances(queries, bounds, distances);
    for (int lane = 0; lane < kPacket; ++lane) {
      // Bit for bit the nearest distance, or the bound when no point lies within it.
      EXPECT_EQ(distances[lane], bruteNearest(points, queries[lane], bounds[lane]))
          << packet << " " << lane;
    }
  }
}

// A models folder and an objects folder of the shapes of RegistrationTest, on disk.
class ClassifyFolderTest : public RegistrationTest {
 protected:
  void SetUp() override {
    RegistrationTest::SetUp();
    std::random_device entropy;
    root_ = fs::temp_directory_path() /
            ("granular_classify_test_" + std::to_string(entropy()) + std::to_string(entropy()));
    fs::create_directories(root_ / "models");
    fs::create_directories(root_ / "objects");
    for (const LabelledModel& model : models_) {
      writeModelPcd(root_ / "models" / (model.label + ".pcd"), model.cloud);
    }
    for (std::size_t i = 0; i < objects_.size(); ++i) {
      writeModelPcd(root_ / "objects" /
                        (models_[truth_[i]].label + "-" + std::to_string(100 + i) + "-1.pcd"),
                    objects_[i]);
    }
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(ClassifyFolderTest, ClassifiesEveryObjectAndWritesItsRecord) {
  const ClassificationRun run =
      classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, converging());
  EXPECT_EQ(run.models, (std::vector<std::string>{"Long", "Tall"}));
  ASSERT_EQ(run.objects.size(), objects_.size());
  EXPECT_EQ(run.summary(2).correct, objects_.size());
  EXPECT_EQ(run.summary(3).correct, objects_.size());
  writeClassificationJson(root_ / "icp.json", run);
  std::ifstream stream(root_ / "icp.json");
  const nlohmann::json json = nlohmann::json::parse(stream);
  EXPECT_EQ(json["method"], "icp");
  EXPECT_EQ(json["objects"].size(), objects_.size());
  const nlohmann::json& first = json["objects"][0];
  EXPECT_EQ(first["true_label"], first["predictions"]["criterion2"]);
  EXPECT_EQ(first["per_model"]["Long"]["transform"].size(), 16u);
  EXPECT_TRUE(first["per_model"]["Tall"].contains("fitness"));
  EXPECT_EQ(json["accuracy"]["criterion2"]["accuracy"], 1.0);
  EXPECT_EQ(json["missing"]["criterion2"], 0);
}

TEST_F(ClassifyFolderTest, AMissingModelIsAWarningAndItsObjectsCountAsWrong) {
  fs::remove(root_ / "models" / "Tall.pcd");
  const ClassificationRun run =
      classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, converging());
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find("Tall (6)"), std::string::npos) << run.warnings[0];
  EXPECT_EQ(run.summary(3).correct, objects_.size() / 2);
}

TEST_F(ClassifyFolderTest, BadFoldersAndFramesAreErrors) {
  EXPECT_THROW(classifyFolder(root_ / "none", root_ / "objects", RegistrationMethod::kIcp, {}),
               std::runtime_error);
  fs::create_directories(root_ / "empty");
  EXPECT_THROW(classifyFolder(root_ / "models", root_ / "empty", RegistrationMethod::kIcp, {}),
               std::runtime_error);
  // A model centred on its box (z = 0 at half height) is not in the objects' frame.
  writeModelPcd(root_ / "models" / "Long.pcd",
                shifted(models_[0].cloud, Eigen::Vector3f(0.0f, 0.0f, -0.7f)));
  try {
    classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, {});
    FAIL() << "a box-centred model was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("Long.pcd"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("box-centre frame"), std::string::npos);
  }
}

TEST_F(ClassifyFolderTest, ObjectClassifierLabelsEveryObjectAndLeavesTinyOnesUnknown) {
  const ObjectClassifier classifier = ObjectClassifier::registration(
      RegistrationMethod::kIcp, converging(), root_ / "models");
  EXPECT_EQ(classifier.method(), "icp");
  EXPECT_EQ(classifier.labels(), (std::vector<std::string>{"Long", "Tall"}));
  std::vector<Cloud> objects;
  for (const ModelCloud& object : objects_) {
    Cloud cloud;
    for (const pcl::PointXYZ& p : object.points) {
      cloud.push_back(PointXYZIT(p.x, p.y, p.z, 0, 0.0));
    }
    objects.push_back(cloud);
  }
  objects.push_back(Cloud());  // nothing to register
  const std::vector<ObjectPrediction> predictions = classifier.classify(objects);
  ASSERT_EQ(predictions.size(), objects.size());
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    EXPECT_TRUE(predictions[i].classified) << i;
    EXPECT_EQ(predictions[i].label, models_[truth_[i]].label) << i;
    // The right model fits far better than the other one.
    EXPECT_GT(predictions[i].score, 0.5) << i;
    EXPECT_LE(predictions[i].score, 1.0) << i;
  }
  EXPECT_FALSE(predictions.back().classified);
  EXPECT_EQ(predictions.back().label, "unknown");
  EXPECT_THROW(ObjectClassifier::registration(RegistrationMethod::kIcp, converging(),
                                              root_ / "no_models"),
               std::runtime_error);
}

}  // namespace
}  // namespace granular
