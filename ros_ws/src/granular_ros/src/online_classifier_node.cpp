// online_classifier: classifies the objects of a LiDAR stream as it arrives. Pairs each cloud
// with its 3-D detections, extracts every detection's points into the object frame (the same
// code as extract_objects), classifies them with a registration or a supervised classifier,
// and publishes the detections with the predicted labels and rviz markers.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <granular_core/online/object_classifier.h>
#include <granular_core/online/track_votes.h>
#include <granular_core/extraction/extract_objects.h>
#include <lgsvl_msgs/Detection3DArray.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <pcl/console/print.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float32.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include "granular_ros/conversions.h"
#include "granular_ros/latency.h"
#include "granular_ros/markers.h"
#include "granular_ros/node_parameters.h"
#include "granular_ros/presets.h"
#include "granular_ros/tool.h"
#include "granular_ros/wall_throttle.h"

namespace {

using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2,
                                                               lgsvl_msgs::Detection3DArray>;

// The node's parameters: config/online.yaml's, and what the launch file sets from its arguments.
struct OnlineClassifierParameters {
  std::string method;  ///< icp, icp_nl, ndt, knn, svm, svm_esf or svm_fitness
  std::string models;  ///< models folder (registration) or classifier file (supervised)
  std::string class_models;  ///< svm_fitness: the models folder it learnt from
  /// A relative `models` is taken from here: roslaunch runs nodes in $ROS_HOME, not where the
  /// user started it.
  std::string relative_to = ".";
  std::string preset = granular_ros::kDefaultPreset;
  std::string registration_config;  ///< presets file (config/classification.yaml); "": none
  std::size_t min_points = 10;
  double slop = 0.01;
  int queue_size = 10;
  Eigen::Vector3d padding = Eigen::Vector3d::Zero();
  int threads = 1;
  double topic_timeout = 5.0;
  double report_interval = 10.0;
  double marker_lifetime = 0.5;
  bool marker_tracks = false;
  bool face_away = false;
  bool track_vote = true;
  bool track_vote_points = true;
  double track_forget = 2.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace granular::config;
    visit("method", self.method,
          optionalText("a method (icp, icp_nl, ndt, knn, svm, svm_esf or svm_fitness)"));
    visit("models", self.models, optionalText("a models folder or a classifier file"));
    visit("class_models", self.class_models, optionalText("a models folder"));
    visit("relative_to", self.relative_to, text("a folder"));
    visit("preset", self.preset, text("a preset name"));
    visit("registration_config", self.registration_config, optionalText("a presets file"));
    visit("min_points", self.min_points, nonNegative("points"));
    visit("slop", self.slop, positive("s"));
    visit("queue_size", self.queue_size, atLeast(1, "messages"));
    visit("padding", self.padding, nonNegative("m"));
    visit("threads", self.threads, atLeast(1));
    visit("topic_timeout", self.topic_timeout, positive("s"));
    visit("report_interval", self.report_interval, positive("s"));
    visit("marker_lifetime", self.marker_lifetime, nonNegative("s"));
    visit("marker_tracks", self.marker_tracks);
    visit("face_away", self.face_away);
    visit("track_vote", self.track_vote);
    visit("track_vote_points", self.track_vote_points);
    visit("track_forget", self.track_forget, positive("s"));
  }
};

void validate(const OnlineClassifierParameters& parameters) {
  if (parameters.method.empty() || parameters.models.empty()) {
    throw std::invalid_argument("parameters ~method and ~models are required");
  }
  granular::config::validateFields(parameters);
}

// The classifier that ~method and ~models name.
granular::ObjectClassifier makeClassifier(const OnlineClassifierParameters& parameters) {
  const std::string& method = parameters.method;
  const auto resolved = [&](const std::filesystem::path& given) {
    return (given.is_relative() ? std::filesystem::path(parameters.relative_to) / given : given)
        .lexically_normal()
        .string();
  };
  const std::string models = resolved(parameters.models);
  std::optional<std::filesystem::path> presets_file;
  if (!parameters.registration_config.empty()) {
    presets_file = parameters.registration_config;
  }
  if (const auto registration = granular::registrationMethodFromName(method)) {
    return granular::ObjectClassifier::registration(
        *registration, granular_ros::resolvePreset(presets_file, parameters.preset), models,
        parameters.threads);
  }
  if (method == "svm_fitness") {
    if (parameters.class_models.empty()) {
      throw std::invalid_argument(
          "~class_models: svm_fitness needs the models folder it learnt from");
    }
    return granular::ObjectClassifier::fitness(
        models, resolved(parameters.class_models),
        [&](const std::string& preset) { return granular_ros::resolvePreset(presets_file, preset); },
        parameters.threads);
  }
  if (const auto supervised = granular::supervisedMethodFromName(method)) {
    granular::ObjectClassifier classifier =
        granular::ObjectClassifier::supervised(models, parameters.threads);
    if (classifier.method() != method) {
      throw std::invalid_argument("~models: " + models + " holds a " + classifier.method() +
                                  " classifier, not " + method);
    }
    return classifier;
  }
  throw std::invalid_argument(
      "~method: expected icp, icp_nl, ndt, knn, svm, svm_esf or svm_fitness, got '" + method +
      "'");
}

class OnlineClassifier {
 public:
  OnlineClassifier(ros::NodeHandle& node, ros::NodeHandle& private_node,
                   const OnlineClassifierParameters& parameters)
      : classifier_(makeClassifier(parameters)),
        min_points_(parameters.min_points),
        marker_lifetime_(parameters.marker_lifetime),
        marker_tracks_(parameters.marker_tracks),
        face_away_(parameters.face_away),
        track_votes_(parameters.track_vote
                         ? std::optional<granular::TrackVotes>(parameters.track_forget)
                         : std::nullopt),
        track_vote_points_(parameters.track_vote_points),
        topic_timeout_(parameters.topic_timeout),
        report_interval_(parameters.report_interval),
        tf_listener_(tf_buffer_),
        cloud_subscriber_(private_node, "cloud", 10),
        detections_subscriber_(private_node, "detections", 10) {
    extraction_.padding = parameters.padding;
    for (const std::string& warning : classifier_.warnings()) {
      ROS_WARN_STREAM("online_classifier: " << warning);
    }
    synchronizer_ = std::make_unique<message_filters::Synchronizer<Policy>>(
        Policy(static_cast<std::uint32_t>(parameters.queue_size)), cloud_subscriber_,
        detections_subscriber_);
    synchronizer_->setMaxIntervalDuration(ros::Duration(parameters.slop));
    synchronizer_->registerCallback(&OnlineClassifier::onFrame, this);
    cloud_subscriber_.registerCallback(
        [this](const sensor_msgs::PointCloud2ConstPtr&) { last_cloud_ = Clock::now(); });
    detections_subscriber_.registerCallback(
        [this](const lgsvl_msgs::Detection3DArrayConstPtr&) { last_detections_ = Clock::now(); });

    detections_publisher_ = private_node.advertise<lgsvl_msgs::Detection3DArray>("output", 10);
    markers_publisher_ = private_node.advertise<visualization_msgs::MarkerArray>("markers", 10);
    latency_publisher_ = private_node.advertise<std_msgs::Float32>("latency_ms", 10);
    watchdog_ = node.createSteadyTimer(ros::WallDuration(1.0), &OnlineClassifier::watch, this);
    ROS_INFO_STREAM("online_classifier: " << classifier_.method() << " over "
                                          << classifier_.labels().size() << " classes, waiting for "
                                          << cloud_subscriber_.getTopic() << " and "
                                          << detections_subscriber_.getTopic());
  }

  ~OnlineClassifier() {
    // Plain stdout: roscpp has shut rosconsole down by the time spin() returns on a signal.
    std::printf("online_classifier: latency over the whole run: %s\n", latency_.total().c_str());
    std::fflush(stdout);
  }

 private:
  using Clock = std::chrono::steady_clock;

  void onFrame(const sensor_msgs::PointCloud2ConstPtr& cloud_message,
               const lgsvl_msgs::Detection3DArrayConstPtr& detections_message) {
    const auto start = Clock::now();
    if (detections_message->detections.empty()) {
      return;  // no object, no frame, as bag_to_files does
    }
    granular::Cloud cloud;
    try {
      cloud = granular_ros::toCloud(*cloud_message);
    } catch (const std::exception& error) {
      if (cloud_warning_.due()) {
        ROS_WARN_STREAM("online_classifier: skipping a cloud: " << error.what());
      }
      return;
    }
    lgsvl_msgs::Detection3DArray output = *detections_message;
    if (!inCloudFrame(output, cloud_message->header)) {
      return;
    }
    std::vector<granular::Detection> boxes = granular_ros::toDetections(output);
    if (face_away_) {
      for (granular::Detection& box : boxes) {
        box = granular::facingAwayFromSensor(std::move(box));
      }
    }
    granular::FrameExtraction extraction = granular::extractObjects(cloud, boxes, extraction_);
    if (!extraction.errors.empty() && extraction_warning_.due()) {
      ROS_WARN_STREAM("online_classifier: " << extraction.errors.front()
                                            << (extraction.errors.size() > 1
                                                    ? " (and " +
                                                          std::to_string(extraction.errors.size() - 1) +
                                                          " more in this frame)"
                                                    : std::string()));
    }
    // Objects too small to classify keep the label "unknown".
    std::vector<granular::Cloud> objects;
    std::vector<std::size_t> classified_index;
    std::map<std::int64_t, std::size_t> object_of_id;
    for (std::size_t k = 0; k < extraction.objects.size(); ++k) {
      if (extraction.objects[k].cloud.size() >= min_points_) {
        object_of_id[extraction.objects[k].detection.id] = objects.size();
        objects.push_back(std::move(extraction.objects[k].cloud));
      }
    }
    const std::vector<granular::ObjectPrediction> predictions = classifier_.classify(objects);

    std::vector<std::string> truth;
    const double stamp = cloud_message->header.stamp.toSec();
    for (lgsvl_msgs::Detection3D& detection : output.detections) {
      truth.push_back(detection.label == "unknown" ? "" : detection.label);
      const auto object = object_of_id.find(detection.id);
      const bool known = object != object_of_id.end() && predictions[object->second].classified;
      detection.label = known ? predictions[object->second].label : "unknown";
      detection.score = known ? static_cast<float>(predictions[object->second].score) : 0.0f;
      if (known && track_votes_) {
        const double weight =
            track_vote_points_ ? static_cast<double>(objects[object->second].size()) : 1.0;
        const granular::TrackLabel track =
            track_votes_->vote(detection.id, detection.label, stamp, weight);
        detection.label = track.label;
        detection.score = static_cast<float>(track.share);
      }
    }
    if (track_votes_) {
      track_votes_->forget(stamp);
    }
    output.header.stamp = cloud_message->header.stamp;
    output.header.frame_id = cloud_message->header.frame_id;
    detections_publisher_.publish(output);
    if (markers_publisher_.getNumSubscribers() > 0) {
      markers_publisher_.publish(granular_ros::predictionMarkers(output, truth, marker_lifetime_,
                                                                  marker_tracks_));
    }
    const double milliseconds =
        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    latency_.add(milliseconds);
    std_msgs::Float32 latency;
    latency.data = static_cast<float>(milliseconds);
    latency_publisher_.publish(latency);
  }

  // Moves the detections into the cloud's frame when they are in another one and tf2 knows the
  // transform; false (the frame is skipped, with one warning per pair of frames) when it does
  // not. An empty frame id (the LGSVL simulator's) means the cloud's frame.
  bool inCloudFrame(lgsvl_msgs::Detection3DArray& detections, const std_msgs::Header& cloud) {
    const std::string& from = detections.header.frame_id;
    if (from.empty() || from == cloud.frame_id) {
      return true;
    }
    geometry_msgs::TransformStamped transform;
    try {
      transform = tf_buffer_.lookupTransform(cloud.frame_id, from, detections.header.stamp);
    } catch (const tf2::TransformException& error) {
      if (warned_frames_.insert(from + " -> " + cloud.frame_id).second) {
        ROS_WARN_STREAM("online_classifier: detections in frame '"
                        << from << "', cloud in '" << cloud.frame_id
                        << "' and no transform between them (" << error.what()
                        << "); skipping such frames");
      }
      return false;
    }
    for (lgsvl_msgs::Detection3D& detection : detections.detections) {
      tf2::doTransform(detection.bbox.position, detection.bbox.position, transform);
    }
    detections.header.frame_id = cloud.frame_id;
    return true;
  }

  // The topics of `type` that the master knows now (the bag's, as it plays), as a clause for a
  // warning about the silent `topic`.
  static std::string publishedOfType(const std::string& type, const std::string& topic) {
    ros::master::V_TopicInfo published;
    if (!ros::master::getTopics(published)) {
      return "the ROS master does not answer";
    }
    std::string others;
    for (const ros::master::TopicInfo& info : published) {
      if (info.datatype == type && info.name != topic) {
        others += (others.empty() ? "" : ", ") + info.name;
      }
    }
    return others.empty() ? "nothing publishes " + type + " now"
                          : "the " + type + " topics published now: " + others;
  }

  // Warns when a topic has been silent for ~topic_timeout seconds, and logs the latency every
  // ~report_interval seconds.
  void watch(const ros::SteadyTimerEvent&) {
    const auto now = Clock::now();
    struct Watched {
      std::string topic;
      std::optional<Clock::time_point> last;
      const char* type;      // what the topic must carry
      const char* argument;  // online.launch's argument that names it
    };
    const Watched topics[] = {
        {cloud_subscriber_.getTopic(), last_cloud_, "sensor_msgs/PointCloud2", "cloud_topic"},
        {detections_subscriber_.getTopic(), last_detections_, "lgsvl_msgs/Detection3DArray",
         "detections_topic"}};
    for (const auto& [topic, last, type, argument] : topics) {
      const double silent = std::chrono::duration<double>(now - last.value_or(started_)).count();
      Clock::time_point& warned = last_warned_[topic];
      if (silent > topic_timeout_ &&
          std::chrono::duration<double>(now - warned).count() > topic_timeout_) {
        ROS_WARN_STREAM("online_classifier: nothing on " << topic << " for "
                                                         << static_cast<int>(silent) << " s; "
                                                         << publishedOfType(type, topic)
                                                         << " (online.launch: " << argument
                                                         << ":=)");
        warned = now;
      }
    }
    if (latency_.frames() > reported_frames_ &&
        std::chrono::duration<double>(now - last_report_).count() >= report_interval_) {
      ROS_INFO_STREAM("online_classifier: latency " << latency_.recent());
      reported_frames_ = latency_.frames();
      last_report_ = now;
    }
  }

  granular::ObjectClassifier classifier_;
  granular::ExtractionConfig extraction_;
  std::size_t min_points_;
  double marker_lifetime_;
  bool marker_tracks_;
  bool face_away_;
  // One vote per frame per detection id (~track_vote); unset: each frame's own label.
  std::optional<granular::TrackVotes> track_votes_;
  bool track_vote_points_;  // each vote weighs its object's points (~track_vote_points)
  double topic_timeout_;
  double report_interval_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> cloud_subscriber_;
  message_filters::Subscriber<lgsvl_msgs::Detection3DArray> detections_subscriber_;
  std::unique_ptr<message_filters::Synchronizer<Policy>> synchronizer_;
  ros::Publisher detections_publisher_;
  ros::Publisher markers_publisher_;
  ros::Publisher latency_publisher_;
  ros::SteadyTimer watchdog_;
  granular_ros::LatencyStats latency_;
  granular_ros::WallThrottle cloud_warning_;
  granular_ros::WallThrottle extraction_warning_;
  std::set<std::string> warned_frames_;
  std::map<std::string, Clock::time_point> last_warned_;  ///< by topic
  const Clock::time_point started_ = Clock::now();
  std::optional<Clock::time_point> last_cloud_;
  std::optional<Clock::time_point> last_detections_;
  Clock::time_point last_report_ = Clock::now();
  std::size_t reported_frames_ = 0;
};

}  // namespace

constexpr char kHelp[] =
    "usage: rosrun granular_ros online_classifier (a ROS node; launch/online.launch starts it)\n"
    "\n"
    "Classifies the objects of a LiDAR stream as it arrives: pairs each cloud (~cloud,\n"
    "sensor_msgs/PointCloud2) with its 3-D detections (~detections, lgsvl_msgs/Detection3DArray)\n"
    "within ~slop, crops every detection's points into its object frame, classifies them with a\n"
    "registration method against class models or a supervised classifier, and publishes the\n"
    "detections with the predicted labels (~output), rviz markers (~markers) and each frame's\n"
    "processing time (~latency_ms). Its parameters are config/online.yaml's (docs/online.md); a\n"
    "misspelt one stops it at start-up, naming the known ones. Needs a ROS master.\n"
    "\n"
    "Exit status: 0 shut down, 1 bad parameters or inputs at start-up.\n";

int main(int argc, char** argv) {
  if (granular_ros::answerNodeHelp(argc, argv, kHelp)) {
    return 0;
  }
  granular_ros::reuseFreedMemory();
  ros::init(argc, argv, "online_classifier");
  ros::NodeHandle node;
  ros::NodeHandle private_node("~");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  std::unique_ptr<OnlineClassifier> classifier;
  try {
    classifier = std::make_unique<OnlineClassifier>(
        node, private_node,
        granular_ros::readNodeParameters<OnlineClassifierParameters>(private_node));
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("online_classifier: " << error.what());
    return 1;
  }
  ros::spin();
  return 0;
}
