// segment_cloud: boxes for clouds without detections (config/ground.yaml: the ground;
// config/segmentation.yaml: the segments; config/cuboids.yaml under ~cuboids: a full-vehicle
// cuboid fitted to each, touching cars cut apart and the zero-shot vehicle decision of
// ~cuboids/evidence on each, as fit_cuboids does; with ~track, config/tracking.yaml under
// ~tracking: the tracker's ids and velocities). Each cloud on ~input becomes a
// Detection3DArray on ~output, one cuboid labelled "unknown" per segment judged a vehicle (per
// born track's cuboid, when tracking), for the online classifier to classify.
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <granular_core/cuboids/cuboid_fitter.h>
#include <granular_core/cuboids/frame_cuboids.h>
#include <granular_core/ground/sensor.h>
#include <granular_core/segmentation/object_segmentation.h>
#include <granular_core/tracking/tracker.h>
#include <lgsvl_msgs/Detection3DArray.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float32.h>

#include "granular_ros/conversions.h"
#include "granular_ros/latency.h"
#include "granular_ros/node_parameters.h"
#include "granular_ros/tool.h"
#include "granular_ros/wall_throttle.h"

namespace {

// The node's parameters: the ground's under ~ground (config/ground.yaml), the cuboids' under
// ~cuboids (config/cuboids.yaml), the segmentation's (config/segmentation.yaml), the sensor's
// under ~sensor when given (config/sensors/NAME.yaml: its height and azimuth step over the
// ground's and the segmentation's), the tracker's under ~tracking (config/tracking.yaml) and its
// own.
struct SegmentCloudParameters {
  granular::GroundConfig ground;
  granular::CuboidConfig cuboids;
  granular::SegmentationStageConfig segmentation;
  granular::SensorConfig sensor;
  granular::TrackingConfig tracking;
  /// Publish the cuboids of born tracks only, each with its track's id and velocity, instead
  /// of every cuboid numbered within its frame.
  bool track = false;
  int threads = 1;  ///< threads fitting a frame's segments (0: every core)
  /// Measure the sensor's height and azimuth step from the first cloud (online.launch
  /// sensor:=auto) instead of taking ~sensor's.
  bool sensor_auto = false;
  double report_interval = 10.0;  ///< s between latency lines in the log

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("ground", self.ground);
    visit("cuboids", self.cuboids);
    granular::SegmentationStageConfig::fields(self.segmentation, visit);
    visit("sensor", self.sensor);
    visit("tracking", self.tracking);
    visit("track", self.track);
    visit("threads", self.threads, granular::config::atLeast(0, "threads"));
    visit("sensor_auto", self.sensor_auto);
    visit("report_interval", self.report_interval, granular::config::positive("s"));
  }
};

void validate(const SegmentCloudParameters& parameters) {
  granular::validate(parameters.sensor);
  granular::validate(parameters.ground);
  granular::validate(parameters.segmentation);
  granular::validate(parameters.cuboids);
  granular::validate(parameters.tracking);
  granular::config::validateFields(parameters);
  if (parameters.cuboids.method == granular::CuboidMethod::kModel) {
    // The class is the online classifier's job; the node has no models.
    throw std::invalid_argument("~cuboids/method: the node fits geometric or rectangle cuboids");
  }
}

class SegmentCloud {
 public:
  explicit SegmentCloud(ros::NodeHandle& node, ros::NodeHandle& private_node) {
    auto parameters = granular_ros::readNodeParameters<SegmentCloudParameters>(private_node);
    // A sensor under ~sensor (online.launch's sensor:=, its sensor_height:= and
    // azimuth_step:= laid over it) gives the ground's height and the segmentation's step.
    if (private_node.hasParam("sensor")) {
      parameters.ground.plane.sensor_height = parameters.sensor.mount_height;
      parameters.segmentation.objects.azimuth_step_deg = parameters.sensor.azimuth_step_deg;
    }
    config_ = parameters.segmentation;
    ground_config_ = parameters.ground;
    cuboid_config_ = parameters.cuboids;
    threads_ = parameters.threads;
    if (parameters.track) {
      tracking_config_ = parameters.tracking;
      tracker_.emplace(*tracking_config_);
    }
    if (!parameters.sensor_auto) {
      segmenter_ = std::make_unique<granular::FrameSegmenter>(ground_config_, config_);
    }
    fitter_ = granular::makeCuboidFitter(parameters.cuboids, {});
    report_interval_ = parameters.report_interval;
    publisher_ = private_node.advertise<lgsvl_msgs::Detection3DArray>("output", 10);
    latency_publisher_ = private_node.advertise<std_msgs::Float32>("latency_ms", 10);
    subscriber_ = private_node.subscribe("input", 2, &SegmentCloud::onCloud, this);
    timer_ = node.createSteadyTimer(ros::WallDuration(report_interval_), [this](const auto&) {
      if (latency_.frames() > 0) {
        ROS_INFO_STREAM("segment_cloud: time per cloud " << latency_.recent());
      }
    });
    ROS_INFO_STREAM("segment_cloud: "
                    << granular::config::enumName(config_.method) << " segmentation, "
                    << granular::config::enumName(parameters.cuboids.method)
                    << " cuboids" << (tracker_ ? ", tracked" : "") << ", on "
                    << subscriber_.getTopic());
  }

  ~SegmentCloud() { ROS_INFO_STREAM("segment_cloud: " << latency_.total()); }

 private:
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& message) {
    const auto start = std::chrono::steady_clock::now();
    granular::Cloud cloud;
    try {
      cloud = granular_ros::toCloud(*message);
    } catch (const std::exception& error) {
      if (cloud_warning_.due()) {
        ROS_WARN_STREAM("segment_cloud: skipping a cloud: " << error.what());
      }
      return;
    }
    if (!segmenter_ && !measureSensor(cloud)) {
      return;
    }
    lgsvl_msgs::Detection3DArray output;
    output.header = message->header;
    const granular::ObjectSegmentation segmentation = segmenter_->segment(cloud);
    if (config_.method == granular::SegmentationMethod::kObjects) {
      const granular::GroundCheck check =
          granular::checkGround(cloud, segmentation.ground.plane, segmentation.ground.inliers,
                                ground_config_, message->header.frame_id);
      if (check.verdict != granular::GroundCheck::Verdict::kGround &&
          ground_warning_.due()) {
        ROS_WARN_STREAM("segment_cloud: the cloud of " << message->header.stamp << " in frame '"
                                                       << message->header.frame_id
                                                       << "': " << check.problem);
      }
    }
    const granular::FrameCuboids cuboids = granular::fitSegmentCuboids(
        cloud, segmentation, config_, cuboid_config_, *fitter_, threads_);
    if (tracker_) {
      publishTracks(message->header, cuboids, output);
    } else {
      for (const granular::FrameCuboid& kept : cuboids.kept) {
        output.detections.push_back(granular_ros::toMessage(
            kept.cuboid.box, "unknown", static_cast<std::uint32_t>(kept.id), 1.0f));
      }
    }
    for (lgsvl_msgs::Detection3D& detection : output.detections) {
      detection.header = message->header;
    }
    publisher_.publish(output);
    const double milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count();
    latency_.add(milliseconds);
    std_msgs::Float32 latency;
    latency.data = static_cast<float>(milliseconds);
    latency_publisher_.publish(latency);
  }

  // The cuboids of the tracks born by this frame that have one in it, each with its track's
  // id and x-y velocity (m/s, sensor frame) and turned to its smoothed yaw; unborn tracks and
  // coasting ones are not published (docs/tracking.md). A stamp not after the last one (a
  // looped bag) starts the tracks afresh.
  void publishTracks(const std_msgs::Header& header, const granular::FrameCuboids& cuboids,
                     lgsvl_msgs::Detection3DArray& output) {
    std::vector<granular::Observation> observations;
    for (const granular::FrameCuboid& kept : cuboids.kept) {
      observations.push_back(
          {kept.cuboid.box, kept.cuboid.label, kept.cuboid.score, kept.cuboid.points});
    }
    std::vector<granular::Track> tracks;
    try {
      tracks = tracker_->update(header.stamp.toSec(), observations);
    } catch (const std::invalid_argument& error) {
      ROS_WARN_STREAM("segment_cloud: " << error.what() << "; the tracks start afresh");
      tracker_.emplace(*tracking_config_);
      tracks = tracker_->update(header.stamp.toSec(), observations);
    }
    for (const granular::Track& track : tracks) {
      if (!track.observation) {
        continue;
      }
      const granular::OrientedBox& box = cuboids.kept[*track.observation].cuboid.box;
      const Eigen::Quaterniond turn =
          granular::turnToTrack(track, box, tracking_config_->max_turn_deg);
      lgsvl_msgs::Detection3D detection = granular_ros::toMessage(
          granular::OrientedBox(box.centre(), turn * box.orientation(), box.size()), "unknown",
          track.id, 1.0f);
      detection.velocity.linear.x = track.velocity.x();
      detection.velocity.linear.y = track.velocity.y();
      output.detections.push_back(detection);
    }
  }

  // sensor:=auto: the sensor measured from `cloud`, the segmenter built with it; a cloud that
  // cannot tell stops the node (it is required), saying why and what to pass instead.
  bool measureSensor(const granular::Cloud& cloud) {
    const granular::SensorEstimate estimate = granular::estimateSensor({cloud}, ground_config_);
    if (!estimate.mount_height || !estimate.azimuth_step_deg) {
      std::string problems;
      for (const std::string& problem : estimate.problems) {
        problems += (problems.empty() ? "" : "; ") + problem;
      }
      ROS_FATAL_STREAM("segment_cloud: sensor:=auto cannot tell from the first cloud: "
                       << problems << "; name the sensor (sensor:=NAME) or give sensor_height:= "
                                      "and azimuth_step:=");
      ros::shutdown();
      return false;
    }
    ground_config_.plane.sensor_height = *estimate.mount_height;
    config_.objects.azimuth_step_deg = *estimate.azimuth_step_deg;
    ROS_INFO("segment_cloud: sensor auto: mount height %.2f m (the road plane under the first "
             "cloud), azimuth step %.3f deg (returns along rings)",
             *estimate.mount_height, *estimate.azimuth_step_deg);
    segmenter_ = std::make_unique<granular::FrameSegmenter>(ground_config_, config_);
    return true;
  }

  granular::SegmentationStageConfig config_;
  granular::GroundConfig ground_config_;
  std::unique_ptr<granular::FrameSegmenter> segmenter_;
  std::unique_ptr<granular::CuboidFitter> fitter_;
  granular::CuboidConfig cuboid_config_;
  int threads_ = 1;
  std::optional<granular::TrackingConfig> tracking_config_;
  std::optional<granular::Tracker> tracker_;
  double report_interval_ = 10.0;
  ros::Subscriber subscriber_;
  ros::Publisher publisher_;
  ros::Publisher latency_publisher_;
  ros::SteadyTimer timer_;
  granular_ros::WallThrottle cloud_warning_;
  granular_ros::WallThrottle ground_warning_;
  granular_ros::LatencyStats latency_;
};

}  // namespace

constexpr char kHelp[] =
    "usage: rosrun granular_ros segment_cloud (a ROS node; online.launch boxes:=segment starts it)\n"
    "\n"
    "Boxes for clouds without detections: each cloud on ~input (sensor_msgs/PointCloud2) becomes a\n"
    "Detection3DArray on ~output, one full-vehicle cuboid labelled \"unknown\" per segment above the\n"
    "ground that the zero-shot vehicle decision keeps (~cuboids/evidence; touching cars cut apart\n"
    "first, ~cuboids/split), as fit_cuboids makes them, for the online classifier, and the cloud's\n"
    "time in ms on ~latency_ms. With ~track true, only the cuboids of born tracks (~tracking:\n"
    "config/tracking.yaml), each with its track's id and velocity (m/s, x-y in the sensor frame);\n"
    "a track is published from its birth on (docs/tracking.md). Parameters: the ground's under\n"
    "~ground (config/ground.yaml), the sensor's under ~sensor (config/sensors/NAME.yaml), the\n"
    "cuboids' under ~cuboids (config/cuboids.yaml), the segmentation's (config/segmentation.yaml),\n"
    "the tracker's under ~tracking and its own (~track; ~threads: threads fitting a frame's\n"
    "segments, default 1; docs/online.md); a misspelt one stops it at start-up, naming the known\n"
    "ones. Needs a ROS master.\n"
    "\n"
    "Exit status: 0 shut down, 1 bad parameters at start-up.\n";

int main(int argc, char** argv) {
  if (granular_ros::answerNodeHelp(argc, argv, kHelp)) {
    return 0;
  }
  granular_ros::reuseFreedMemory();
  ros::init(argc, argv, "segment_cloud");
  ros::NodeHandle node;
  ros::NodeHandle private_node("~");
  std::unique_ptr<SegmentCloud> segmenter;
  try {
    segmenter = std::make_unique<SegmentCloud>(node, private_node);
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("segment_cloud: " << error.what());
    return 1;
  }
  ros::spin();
  return 0;
}
