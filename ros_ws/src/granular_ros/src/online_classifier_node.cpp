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
#include <vector>

#include <granular_core/classification/object_classifier.h>
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

#include "granular_ros/classification_config_yaml.h"
#include "granular_ros/conversions.h"
#include "granular_ros/latency.h"
#include "granular_ros/markers.h"

namespace {

using Policy = message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2,
                                                               lgsvl_msgs::Detection3DArray>;

// A required private parameter, or an error naming it.
template <typename T>
T required(const ros::NodeHandle& node, const std::string& name) {
  T value;
  if (!node.getParam(name, value)) {
    throw std::invalid_argument("parameter ~" + name + " is required");
  }
  return value;
}

// The classifier that ~method and ~models name.
granular::ObjectClassifier makeClassifier(const ros::NodeHandle& node) {
  const std::string method = required<std::string>(node, "method");
  // A relative path is taken from ~relative_to: roslaunch runs nodes in $ROS_HOME, not where
  // the user started it.
  const std::filesystem::path given = required<std::string>(node, "models");
  const std::string models =
      (given.is_relative() ? std::filesystem::path(node.param<std::string>("relative_to", ".")) /
                                 given
                           : given)
          .lexically_normal()
          .string();
  const int threads = node.param("threads", 1);
  if (const auto registration = granular::registrationMethodFromName(method)) {
    std::map<std::string, granular::RegistrationClassifierConfig> presets =
        granular::registrationPresets();
    const std::string file = node.param<std::string>("registration_config", "");
    if (!file.empty()) {
      granular_ros::loadRegistrationPresets(file, presets);
    }
    const std::string preset = node.param<std::string>("preset", "tuned");
    if (presets.count(preset) == 0) {
      throw std::invalid_argument("~preset: no preset '" + preset + "'");
    }
    return granular::ObjectClassifier::registration(*registration, presets.at(preset), models,
                                                    threads);
  }
  if (const auto supervised = granular::supervisedMethodFromName(method)) {
    granular::ObjectClassifier classifier = granular::ObjectClassifier::supervised(models, threads);
    if (classifier.method() != method) {
      throw std::invalid_argument("~models: " + models + " holds a " + classifier.method() +
                                  " classifier, not " + method);
    }
    return classifier;
  }
  throw std::invalid_argument("~method: expected icp, icp_nl, ndt, knn, svm or svm_esf, got '" +
                              method + "'");
}

class OnlineClassifier {
 public:
  OnlineClassifier(ros::NodeHandle& node, ros::NodeHandle& private_node)
      : classifier_(makeClassifier(private_node)),
        min_points_(static_cast<std::size_t>(private_node.param("min_points", 10))),
        marker_lifetime_(private_node.param("marker_lifetime", 0.5)),
        topic_timeout_(private_node.param("topic_timeout", 5.0)),
        report_interval_(private_node.param("report_interval", 10.0)),
        tf_listener_(tf_buffer_),
        cloud_subscriber_(private_node, "cloud", 10),
        detections_subscriber_(private_node, "detections", 10) {
    std::vector<double> padding = private_node.param("padding", std::vector<double>{0, 0, 0});
    if (padding.size() != 3) {
      throw std::invalid_argument("~padding: expected [x, y, z] in metres");
    }
    extraction_.padding = Eigen::Vector3d(padding[0], padding[1], padding[2]);
    const double slop = private_node.param("slop", 0.01);
    const int queue_size = private_node.param("queue_size", 10);
    if (!(slop > 0.0) || queue_size < 1) {
      throw std::invalid_argument("~slop must be positive and ~queue_size at least 1");
    }
    for (const std::string& warning : classifier_.warnings()) {
      ROS_WARN_STREAM("online_classifier: " << warning);
    }
    synchronizer_ = std::make_unique<message_filters::Synchronizer<Policy>>(
        Policy(static_cast<std::uint32_t>(queue_size)), cloud_subscriber_,
        detections_subscriber_);
    synchronizer_->setMaxIntervalDuration(ros::Duration(slop));
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
      ROS_WARN_STREAM_THROTTLE(10.0, "online_classifier: skipping a cloud: " << error.what());
      return;
    }
    lgsvl_msgs::Detection3DArray output = *detections_message;
    if (!inCloudFrame(output, cloud_message->header)) {
      return;
    }
    const granular::FrameExtraction extraction =
        granular::extractObjects(cloud, granular_ros::toDetections(output), extraction_);
    for (const std::string& error : extraction.errors) {
      ROS_WARN_STREAM_THROTTLE(10.0, "online_classifier: " << error);
    }
    // Objects too small to classify keep the label "unknown".
    std::vector<granular::Cloud> objects;
    std::vector<std::size_t> classified_index;
    std::map<std::int64_t, std::size_t> object_of_id;
    for (std::size_t k = 0; k < extraction.objects.size(); ++k) {
      if (extraction.objects[k].cloud.size() >= min_points_) {
        object_of_id[extraction.objects[k].detection.id] = objects.size();
        objects.push_back(extraction.objects[k].cloud);
      }
    }
    const std::vector<granular::ObjectPrediction> predictions = classifier_.classify(objects);

    std::vector<std::string> truth;
    for (lgsvl_msgs::Detection3D& detection : output.detections) {
      truth.push_back(detection.label == "unknown" ? "" : detection.label);
      const auto object = object_of_id.find(detection.id);
      const bool known = object != object_of_id.end() && predictions[object->second].classified;
      detection.label = known ? predictions[object->second].label : "unknown";
      detection.score = known ? static_cast<float>(predictions[object->second].score) : 0.0f;
    }
    output.header.stamp = cloud_message->header.stamp;
    output.header.frame_id = cloud_message->header.frame_id;
    detections_publisher_.publish(output);
    if (markers_publisher_.getNumSubscribers() > 0) {
      markers_publisher_.publish(granular_ros::predictionMarkers(output, truth, marker_lifetime_));
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

  // Warns when a topic has been silent for ~topic_timeout seconds, and logs the latency every
  // ~report_interval seconds.
  void watch(const ros::SteadyTimerEvent&) {
    const auto now = Clock::now();
    const std::pair<std::string, std::optional<Clock::time_point>> topics[] = {
        {cloud_subscriber_.getTopic(), last_cloud_},
        {detections_subscriber_.getTopic(), last_detections_}};
    for (const auto& [topic, last] : topics) {
      const double silent = std::chrono::duration<double>(now - last.value_or(started_)).count();
      Clock::time_point& warned = last_warned_[topic];
      if (silent > topic_timeout_ &&
          std::chrono::duration<double>(now - warned).count() > topic_timeout_) {
        ROS_WARN_STREAM("online_classifier: nothing on " << topic << " for "
                                                         << static_cast<int>(silent) << " s");
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
  std::set<std::string> warned_frames_;
  std::map<std::string, Clock::time_point> last_warned_;  ///< by topic
  const Clock::time_point started_ = Clock::now();
  std::optional<Clock::time_point> last_cloud_;
  std::optional<Clock::time_point> last_detections_;
  Clock::time_point last_report_ = Clock::now();
  std::size_t reported_frames_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "online_classifier");
  ros::NodeHandle node;
  ros::NodeHandle private_node("~");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  std::unique_ptr<OnlineClassifier> classifier;
  try {
    classifier = std::make_unique<OnlineClassifier>(node, private_node);
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("online_classifier: " << error.what());
    return 1;
  }
  ros::spin();
  return 0;
}
