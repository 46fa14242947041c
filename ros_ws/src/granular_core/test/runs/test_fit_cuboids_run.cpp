// fitCuboidsFolder: a frames folder to a folder of fitted cuboids, from segments or from given
// boxes.
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/dataset/detections.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/online/object_classifier.h"
#include "granular_core/runs/fit_cuboids_run.h"
#include "support/detections_json.h"
#include "support/temporary_folder.h"
#include "support/visible_faces.h"

namespace granular {
namespace {
using testing_support::detectionJson;
using testing_support::frameJson;
using testing_support::seenFaces;
using testing_support::StandingBox;
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

constexpr double kSensorHeight = 1.73;

// Two frames: a road 1.73 m below the sensor with a 4.5 x 1.8 x 1.5 m car on it, 20 deg off the
// x axis; the first with a detections file (the car's box given along x, a broken box and a box
// of nothing), the second without one.
class FitCuboidsFolderTest : public TemporaryFolderTest {
 protected:
  const std::string stamp_ = "1586102742000765440";
  const std::string bare_stamp_ = "1586102743000000000";

  void SetUp() override {
    TemporaryFolderTest::SetUp();
    frames_ = root_ / "frames";
    car_.centre = {10.0, 3.0};
    car_.yaw = 20.0 * M_PI / 180.0;
    const Cloud cloud = scene({car_});
    fs::create_directories(frames_ / "pcd");
    writePcdBinary(frames_ / "pcd" / (stamp_ + ".pcd"), cloud);
    writePcdBinary(frames_ / "pcd" / (bare_stamp_ + ".pcd"), cloud);
    write(frames_ / "detections_3d" / (stamp_ + ".json"),
          frameJson(detectionJson(136, "Sedan", R"({"x": 10.0, "y": 3.0, "z": -0.98})",
                                  R"({"x": 4.5, "y": 1.8, "z": 1.5})") +
                    "," +
                    detectionJson(137, "Sedan", R"({"x": 0.0, "y": 0.0, "z": 0.0})",
                                  R"({"x": 0.0, "y": 1.8, "z": 1.5})") +
                    "," +
                    detectionJson(138, "Decoy", R"({"x": -20.0, "y": 5.0, "z": -0.98})",
                                  R"({"x": 4.5, "y": 1.8, "z": 1.5})")));
  }

  // root_/drive/pcd: `frames` clouds 0.1 s apart (stamps from the names) of the car driving
  // along its heading at 10 m/s; frame k holds the cars `seen(k, car)` gives for the car
  // there then. Their stamps.
  std::vector<std::string> writeDrive(
      int frames,
      const std::function<std::vector<StandingBox>(int, const StandingBox&)>& seen) const {
    fs::create_directories(root_ / "drive" / "pcd");
    const Eigen::Vector2d heading(std::cos(car_.yaw), std::sin(car_.yaw));
    std::vector<std::string> stamps;
    for (int k = 0; k < frames; ++k) {
      StandingBox car = car_;
      car.centre += 1.0 * k * heading;
      stamps.push_back(std::to_string(1586102742000000000LL + 100000000LL * k));
      writePcdBinary(root_ / "drive" / "pcd" / (stamps.back() + ".pcd"), scene(seen(k, car)));
    }
    return stamps;
  }

  // The road and the faces of the cars the sensor sees.
  static Cloud scene(const std::vector<StandingBox>& cars) {
    Cloud cloud;
    for (double range = 3.0; range < 40.0; range *= 1.03) {
      for (double azimuth = -M_PI; azimuth < M_PI; azimuth += 0.4 * M_PI / 180.0) {
        cloud.push_back(PointXYZIT(static_cast<float>(range * std::cos(azimuth)),
                                   static_cast<float>(range * std::sin(azimuth)),
                                   static_cast<float>(-kSensorHeight), 0, 0.0));
      }
    }
    for (const StandingBox& car : cars) {
      for (const Eigen::Vector3d& p :
           seenFaces(car, Eigen::Vector3d(0, 0, kSensorHeight), 0.05)) {
        cloud.push_back(PointXYZIT(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                   static_cast<float>(p.z() - kSensorHeight), 0, 0.0));
      }
    }
    return cloud;
  }

  // The test car's size as the only prior.
  static CuboidConfig carPrior() {
    CuboidConfig config;
    config.priors = {{"Car", {4.5, 1.8, 1.5}}};
    config.geometric.classes = {"Car"};
    // Exact returns: the paper's d0. The default's 0.1 m, for a real sensor's noise, leaves the
    // closeness flat within about a degree of an exact corner.
    config.lshape.closeness_d0 = 0.01;
    // The car here is a box's faces, not a scan: the vehicle decision, which would call its
    // level top a wall's, is tested in test_vehicle_evidence (and once below).
    config.evidence.enabled = false;
    return config;
  }

  static FitCuboidsOptions options(CuboidInputs boxes) {
    FitCuboidsOptions options;
    options.boxes = boxes;
    options.ground.plane.sensor_height = kSensorHeight;
    options.ground.plane.seed_half_fov_deg = 180.0;
    return options;
  }

  // The car's cuboid: centre within 2 cm, heading within 0.5 deg, the prior's size.
  void expectTheCar(const Detection& cuboid) const {
    const Eigen::Vector3d centre(car_.centre.x(), car_.centre.y(), 0.75 - kSensorHeight);
    EXPECT_LT((cuboid.centre - centre).norm(), 0.02);
    const OrientedBox box(cuboid.centre, cuboid.orientation, cuboid.size);
    EXPECT_LT(std::abs(std::remainder(box.yaw() - car_.yaw, M_PI)) * 180.0 / M_PI, 0.5);
    EXPECT_NEAR(cuboid.size.x(), 4.5, 0.02);
    EXPECT_NEAR(cuboid.size.y(), 1.8, 0.02);
    EXPECT_EQ(cuboid.label, kUnknownLabel);
    EXPECT_EQ(cuboid.score, 1.0);
  }

  fs::path frames_;
  StandingBox car_;
};

TEST_F(FitCuboidsFolderTest, GivenBoxesAreGrownAndRefittedWithoutTheirHeading) {
  const fs::path out = root_ / "cuboids";
  const FitCuboidsSummary summary =
      fitCuboidsFolder(frames_, out, carPrior(), options(CuboidInputs::kDetections));
  EXPECT_EQ(summary.frames, 1u);
  ASSERT_EQ(summary.frames_skipped.size(), 1u);
  EXPECT_EQ(summary.frames_skipped[0], bare_stamp_ + ": no detections_3d/" + bare_stamp_ + ".json");
  ASSERT_EQ(summary.invalid_detections.size(), 1u);
  EXPECT_NE(summary.invalid_detections[0].find("detections[1] (id 137, Sedan): "),
            std::string::npos)
      << summary.invalid_detections[0];
  EXPECT_EQ(summary.objects, 2u);  // the car and the box of nothing
  EXPECT_EQ(summary.fitted, 1u);
  EXPECT_EQ(summary.milliseconds.size(), 2u);
  EXPECT_FALSE(fs::exists(out / (bare_stamp_ + ".json")));
  EXPECT_TRUE(fs::exists(out / kManifestName));

  DetectionsHeader header;
  const std::vector<Detection> cuboids = readDetectionsJson(out / (stamp_ + ".json"), &header);
  EXPECT_EQ(header.secs, 1586102742);
  EXPECT_EQ(header.frame_id, "velodyne");
  ASSERT_EQ(cuboids.size(), 1u);
  EXPECT_EQ(cuboids[0].id, 136);
  expectTheCar(cuboids[0]);
}

TEST_F(FitCuboidsFolderTest, SegmentsAreFittedAndTheFramesBoxesNeverRead) {
  const fs::path out = root_ / "cuboids";
  const FitCuboidsSummary summary =
      fitCuboidsFolder(frames_, out, carPrior(), options(CuboidInputs::kSegments));
  EXPECT_EQ(summary.frames, 2u);
  EXPECT_TRUE(summary.frames_skipped.empty());
  for (const std::string& stamp : {stamp_, bare_stamp_}) {
    DetectionsHeader header;
    const std::vector<Detection> cuboids = readDetectionsJson(out / (stamp + ".json"), &header);
    ASSERT_EQ(cuboids.size(), 1u) << stamp;
    EXPECT_EQ(cuboids[0].id, 0);
    expectTheCar(cuboids[0]);
    // A frame without a detections file takes its header's stamp from its name.
    EXPECT_EQ(header.secs * 1000000000LL + header.nsecs, std::stoll(stamp));
  }
}

TEST_F(FitCuboidsFolderTest, TheVehicleDecisionDropsSegmentsAndCountsWhy) {
  CuboidConfig config = carPrior();
  // The scene is not ray-cast: the road's rings go on behind the box's faces, as rays through
  // foliage do.
  config.evidence.enabled = true;
  const fs::path out = root_ / "cuboids";
  const FitCuboidsSummary summary =
      fitCuboidsFolder(frames_, out, config, options(CuboidInputs::kSegments));
  EXPECT_EQ(summary.fitted, 0u);
  EXPECT_EQ(summary.not_vehicles, (std::map<std::string, std::size_t>{{"see_through", 2}}));
  EXPECT_TRUE(readDetectionsJson(out / (stamp_ + ".json")).empty());
}

TEST_F(FitCuboidsFolderTest, SegmentsDoNotNeedAReadableDetectionsFile) {
  // Before, a malformed detections file failed the whole run, boxes it never uses.
  write(frames_ / "detections_3d" / (stamp_ + ".json"), "{\"detections\": [");
  const FitCuboidsSummary summary = fitCuboidsFolder(frames_, root_ / "cuboids", carPrior(),
                                                     options(CuboidInputs::kSegments));
  EXPECT_EQ(summary.frames, 2u);
  ASSERT_EQ(summary.invalid_detections.size(), 1u);
  EXPECT_NE(summary.invalid_detections[0].find(stamp_ + ".json"), std::string::npos)
      << summary.invalid_detections[0];
  const std::vector<Detection> cuboids =
      readDetectionsJson(root_ / "cuboids" / (stamp_ + ".json"));
  ASSERT_EQ(cuboids.size(), 1u);
  expectTheCar(cuboids[0]);
}

// The surface of a box of `size` standing on the road, in the object frame, every 5 cm.
ModelCloud boxSurface(const Eigen::Vector3d& size) {
  ModelCloud cloud;
  const double step = 0.05;
  for (double u = -size.x() / 2; u <= size.x() / 2 + 1e-9; u += step) {
    for (double v = -size.y() / 2; v <= size.y() / 2 + 1e-9; v += step) {
      for (double w = 0.0; w <= size.z() + 1e-9; w += step) {
        const bool on_face = std::abs(std::abs(u) - size.x() / 2) < 1e-9 ||
                             std::abs(std::abs(v) - size.y() / 2) < 1e-9 ||
                             std::abs(w - size.z()) < 1e-9;
        if (on_face) {
          cloud.push_back(pcl::PointXYZ(static_cast<float>(u), static_cast<float>(v),
                                        static_cast<float>(w)));
        }
      }
    }
  }
  return cloud;
}

TEST_F(FitCuboidsFolderTest, TheNamerNamesEachSegmentsCuboidFromItsCroppedPoints) {
  // Class models of the car's box and of a bus's: the car's cuboid, cropped in its object
  // frame, registers onto the car's.
  fs::create_directories(root_ / "models");
  writeModelPcd(root_ / "models" / "Bus.pcd", boxSurface({12.0, 2.5, 3.0}));
  writeModelPcd(root_ / "models" / "Hatchback.pcd", boxSurface({4.5, 1.8, 1.5}));
  const ObjectClassifier namer = ObjectClassifier::registration(
      RegistrationMethod::kIcp, RegistrationClassifierConfig{}, root_ / "models");
  FitCuboidsOptions named = options(CuboidInputs::kSegments);
  named.namer = &namer;
  const fs::path out = root_ / "cuboids";
  const FitCuboidsSummary summary = fitCuboidsFolder(frames_, out, carPrior(), named);
  EXPECT_EQ(summary.namer, "icp");
  EXPECT_EQ(summary.not_named, 0u);
  EXPECT_EQ(summary.labels, (std::map<std::string, std::size_t>{{"Hatchback", 2}}));
  for (const std::string& stamp : {stamp_, bare_stamp_}) {
    const std::vector<Detection> cuboids = readDetectionsJson(out / (stamp + ".json"));
    ASSERT_EQ(cuboids.size(), 1u) << stamp;
    EXPECT_EQ(cuboids[0].label, "Hatchback");
    EXPECT_GT(cuboids[0].score, 0.5);  // 1 - its fitness / the bus's: far the better
  }
}

TEST_F(FitCuboidsFolderTest, TrackedCuboidsCarryTheirTracksIdAndVelocity) {
  // Five frames 0.1 s apart (stamps from the names) of the car driving along its heading at
  // 10 m/s, and in frame 3 a parked car that is gone in frame 4. The car's track is born in
  // frame 2 and written from frame 0 on; the parked car's never is.
  const fs::path drive = root_ / "drive";
  const Eigen::Vector2d heading(std::cos(car_.yaw), std::sin(car_.yaw));
  StandingBox parked;
  parked.centre = {-12.0, -6.0};
  const std::vector<std::string> stamps = writeDrive(5, [&](int k, const StandingBox& car) {
    return k == 3 ? std::vector<StandingBox>{car, parked} : std::vector<StandingBox>{car};
  });
  FitCuboidsOptions tracked = options(CuboidInputs::kSegments);
  tracked.tracking = TrackingConfig();
  tracked.tracking->birth_hits = 3;
  const FitCuboidsSummary summary =
      fitCuboidsFolder(drive, root_ / "tracked", carPrior(), tracked);
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_EQ(summary.tracks, 1u);
  EXPECT_EQ(summary.tentative, 1u);
  EXPECT_EQ(summary.fitted, 5u);
  std::vector<Detection> written;
  for (int k = 0; k < 5; ++k) {
    const std::vector<Detection> cuboids =
        readDetectionsJson(root_ / "tracked" / (stamps[k] + ".json"));
    ASSERT_EQ(cuboids.size(), 1u) << "frame " << k;
    EXPECT_EQ(cuboids[0].id, 1);
    EXPECT_EQ(cuboids[0].label, kUnknownLabel);  // nothing voted: the cuboid's own
    written.push_back(cuboids[0]);
  }
  // The frames before the birth carry the velocity the track had when born.
  EXPECT_EQ(written[0].velocity, written[2].velocity);
  EXPECT_EQ(written[1].velocity, written[2].velocity);
  EXPECT_LT((written[4].velocity.head<2>() - 10.0 * heading).norm(), 1.0)
      << written[4].velocity.transpose();
  EXPECT_LT((written[0].centre.head<2>() - car_.centre).norm(), 0.05);
  // Without tracking: every cuboid, numbered in its frame, at rest.
  const FitCuboidsSummary untracked =
      fitCuboidsFolder(drive, root_ / "untracked", carPrior(), options(CuboidInputs::kSegments));
  EXPECT_EQ(untracked.fitted, 6u);
  const std::vector<Detection> crowded =
      readDetectionsJson(root_ / "untracked" / (stamps[3] + ".json"));
  ASSERT_EQ(crowded.size(), 2u);
  EXPECT_EQ(crowded[0].id, 0);
  EXPECT_EQ(crowded[1].id, 1);
  EXPECT_EQ(crowded[0].velocity, Eigen::Vector3d::Zero());
}

TEST_F(FitCuboidsFolderTest, ATrackedCuboidCarriesItsTracksFinalClassInEveryFrame) {
  // Six frames of the car driving away, seen 1.5 m high in the first three and 3 m high in the
  // last three (as a van whose top the first frames' view cut): the namer calls it Low, then
  // Tall, and the taller frames' points outweigh the first ones' by the end.
  fs::create_directories(root_ / "models");
  writeModelPcd(root_ / "models" / "Low.pcd", boxSurface({4.5, 1.8, 1.5}));
  writeModelPcd(root_ / "models" / "Tall.pcd", boxSurface({4.5, 1.8, 3.0}));
  const ObjectClassifier namer = ObjectClassifier::registration(
      RegistrationMethod::kIcp, RegistrationClassifierConfig{}, root_ / "models");
  const std::vector<std::string> stamps = writeDrive(6, [](int k, StandingBox car) {
    car.size.z() = k < 3 ? 1.5 : 3.0;
    return std::vector<StandingBox>{car};
  });
  const auto labels = [&](bool final_class) {
    FitCuboidsOptions tracked = options(CuboidInputs::kSegments);
    tracked.namer = &namer;
    tracked.tracking = TrackingConfig();
    tracked.tracking->birth_hits = 3;
    tracked.tracking->final_class = final_class;
    const fs::path out = root_ / (final_class ? "final" : "so_far");
    const FitCuboidsSummary summary = fitCuboidsFolder(root_ / "drive", out, carPrior(), tracked);
    std::vector<std::string> written;
    std::map<std::string, std::size_t> counted;
    for (const std::string& stamp : stamps) {
      const std::vector<Detection> cuboids = readDetectionsJson(out / (stamp + ".json"));
      written.push_back(cuboids.size() == 1 ? cuboids[0].label : "none");
      ++counted[written.back()];
    }
    EXPECT_EQ(summary.labels, counted);  // the summary counts what was written
    return written;
  };
  const std::vector<std::string> so_far = labels(false);
  EXPECT_EQ(so_far[0], "Low");
  EXPECT_EQ(so_far[5], "Tall");
  EXPECT_EQ(labels(true), std::vector<std::string>(6, "Tall"));
}

TEST_F(FitCuboidsFolderTest, AFrameATrackCoastedThroughIsBridged) {
  // Seven frames 0.1 s apart of the car driving along its heading at 10 m/s, its points gone
  // in frame 4: with bridge_frames 1 frame 4 is written with the track's cuboid halfway
  // between frames 3 and 5 (the car's place then, 4 m on), with 0 it holds none.
  const fs::path drive = root_ / "drive";
  const Eigen::Vector2d heading(std::cos(car_.yaw), std::sin(car_.yaw));
  const std::vector<std::string> stamps = writeDrive(7, [](int k, const StandingBox& car) {
    return k == 4 ? std::vector<StandingBox>{} : std::vector<StandingBox>{car};
  });
  const auto run = [&](std::size_t bridge_frames, const std::string& out) {
    FitCuboidsOptions tracked = options(CuboidInputs::kSegments);
    tracked.tracking = TrackingConfig();
    tracked.tracking->birth_hits = 3;
    tracked.tracking->bridge_frames = bridge_frames;
    const FitCuboidsSummary summary = fitCuboidsFolder(drive, root_ / out, carPrior(), tracked);
    return std::make_pair(summary, readDetectionsJson(root_ / out / (stamps[4] + ".json")));
  };
  const auto [bridged, frame4] = run(1, "bridged");
  EXPECT_EQ(bridged.bridging, 1u);
  EXPECT_EQ(bridged.fitted, 7u);
  ASSERT_EQ(frame4.size(), 1u);
  EXPECT_EQ(frame4[0].id, 1);
  const std::vector<Detection> frame3 =
      readDetectionsJson(root_ / "bridged" / (stamps[3] + ".json"));
  const std::vector<Detection> frame5 =
      readDetectionsJson(root_ / "bridged" / (stamps[5] + ".json"));
  ASSERT_EQ(frame3.size(), 1u);
  ASSERT_EQ(frame5.size(), 1u);
  // Halfway to the precision the JSON keeps.
  EXPECT_LT((frame4[0].centre - 0.5 * (frame3[0].centre + frame5[0].centre)).norm(), 1e-4);
  EXPECT_LT((frame4[0].centre.head<2>() - (car_.centre + 4.0 * heading)).norm(), 0.1);
  const auto [unbridged, empty4] = run(0, "unbridged");
  EXPECT_EQ(unbridged.bridging, 0u);
  EXPECT_EQ(unbridged.fitted, 6u);
  EXPECT_TRUE(empty4.empty());
}

TEST_F(FitCuboidsFolderTest, ATracksFramesBeforeAnEndedRunAreWrittenWithBackfillGap) {
  // Seven frames 0.1 s apart of the car driving along its heading at 10 m/s, its points gone
  // in frame 2, and a parked car seen in frames 0 and 1 only. Births after 3 frames: the car's
  // track is born in frame 5. With backfill_gap 1 it is written in frames 0, 1 and 3-6, with
  // 0 in frames 3-6 only; the parked car is written in no frame.
  const fs::path drive = root_ / "drive";
  StandingBox parked;
  parked.centre = {-12.0, -6.0};
  const std::vector<std::string> stamps = writeDrive(7, [&](int k, const StandingBox& car) {
    std::vector<StandingBox> seen;
    if (k != 2) seen.push_back(car);
    if (k < 2) seen.push_back(parked);
    return seen;
  });
  const auto written = [&](std::size_t backfill_gap, const std::string& out) {
    FitCuboidsOptions tracked = options(CuboidInputs::kSegments);
    tracked.tracking = TrackingConfig();
    tracked.tracking->birth_hits = 3;
    tracked.tracking->backfill_gap = backfill_gap;
    fitCuboidsFolder(drive, root_ / out, carPrior(), tracked);
    std::vector<std::vector<int>> ids;
    for (const std::string& stamp : stamps) {
      ids.emplace_back();
      for (const Detection& cuboid : readDetectionsJson(root_ / out / (stamp + ".json"))) {
        ids.back().push_back(cuboid.id);
      }
    }
    return ids;
  };
  EXPECT_EQ(written(1, "kept"), (std::vector<std::vector<int>>{{1}, {1}, {}, {1}, {1}, {1}, {1}}));
  EXPECT_EQ(written(0, "dropped"),
            (std::vector<std::vector<int>>{{}, {}, {}, {1}, {1}, {1}, {1}}));
}

TEST_F(FitCuboidsFolderTest, TrackingRefusesFramesWhoseStampsDoNotIncrease) {
  // The second frame's detections file gives it the first frame's stamp.
  write(frames_ / "detections_3d" / (bare_stamp_ + ".json"), frameJson(""));
  FitCuboidsOptions tracked = options(CuboidInputs::kSegments);
  tracked.tracking = TrackingConfig();
  try {
    fitCuboidsFolder(frames_, root_ / "tracked", carPrior(), tracked);
    FAIL() << "frames with one stamp were tracked";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(bare_stamp_ + ".pcd: tracking needs frames in "
                                             "increasing stamps"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(root_ / "tracked"));
}

TEST_F(FitCuboidsFolderTest, BadInputIsNamed) {
  EXPECT_THROW(fitCuboidsFolder(root_ / "absent", root_ / "out", carPrior(),
                                options(CuboidInputs::kSegments)),
               std::runtime_error);
  CuboidConfig model = carPrior();
  model.method = CuboidMethod::kModel;
  EXPECT_THROW(fitCuboidsFolder(frames_, root_ / "out", model, options(CuboidInputs::kSegments)),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(root_ / "out"));
  write("others/file.txt", "not ours");
  try {
    fitCuboidsFolder(frames_, root_ / "others", carPrior(), options(CuboidInputs::kSegments));
    FAIL() << "a folder of other files was replaced";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("others"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace granular
