// fit_cuboid_server: the labelling tool's new boxes (label_cuboids, a click with rviz's Publish
// Point). The service fit_cuboid (granular_ros/FitCuboid) fits a cuboid around a clicked point
// of a frame's PCD with granular_core's fitCuboidAtClick; its private parameters are
// config/cuboids.yaml's (the click:, points: and lshape: sections count).
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <granular_core/cuboids/click_fit.h>
#include <granular_core/dataset/pcd_io.h>
#include <ros/ros.h>

#include "granular_ros/FitCuboid.h"
#include "granular_ros/conversions.h"
#include "granular_ros/node_parameters.h"

namespace {

namespace fs = std::filesystem;

class FitCuboidServer {
 public:
  FitCuboidServer(ros::NodeHandle& node, const ros::NodeHandle& private_node)
      : config_(granular_ros::readNodeParameters<granular::CuboidConfig>(private_node)),
        service_(node.advertiseService("fit_cuboid", &FitCuboidServer::fit, this)) {
    ROS_INFO_STREAM("fit_cuboid_server: fitting clicked boxes on " << service_.getService());
  }

 private:
  bool fit(granular_ros::FitCuboid::Request& request, granular_ros::FitCuboid::Response& response) {
    try {
      const std::vector<Eigen::Vector3d>& cloud = load(request.cloud_file);
      const granular::SizePrior size{request.size.x, request.size.y, request.size.z};
      const granular::ClickedCuboid clicked = granular::fitCuboidAtClick(
          cloud, Eigen::Vector3d(request.click.x, request.click.y, request.click.z),
          request.label, size, config_);
      response.cuboid = granular_ros::toMessage(clicked.cuboid.box, clicked.cuboid.label, 0,
                                                static_cast<float>(clicked.cuboid.score));
      response.points = static_cast<std::uint32_t>(clicked.cuboid.points);
      response.ground = clicked.ground;
    } catch (const std::exception& error) {  // a bad file, click or size: the caller says why
      const std::string why = error.what();
      // Each answer names the frame's file; readPcd's own errors already do.
      response.error = why.rfind(request.cloud_file, 0) == 0 ? why
                                                             : request.cloud_file + ": " + why;
    }
    return true;
  }

  // The finite points of `file`, read again only when it is another file or has changed.
  const std::vector<Eigen::Vector3d>& load(const std::string& file) {
    std::error_code error;
    const fs::file_time_type modified = fs::last_write_time(file, error);
    if (error) {
      throw std::runtime_error("cannot read: " + error.message());
    }
    if (file != loaded_file_ || modified != loaded_time_) {
      const granular::Cloud cloud = granular::readPcd(file);
      points_.clear();
      for (const auto& point : cloud.points) {
        const Eigen::Vector3d xyz(point.x, point.y, point.z);
        if (xyz.allFinite()) {
          points_.push_back(xyz);
        }
      }
      loaded_file_ = file;
      loaded_time_ = modified;
    }
    return points_;
  }

  granular::CuboidConfig config_;
  ros::ServiceServer service_;
  std::string loaded_file_;
  fs::file_time_type loaded_time_;
  std::vector<Eigen::Vector3d> points_;
};

}  // namespace

constexpr char kHelp[] =
    "usage: rosrun granular_ros fit_cuboid_server (a ROS node; launch/label_cuboids.launch starts it)\n"
    "\n"
    "The labelling tool's new boxes: the service fit_cuboid (granular_ros/FitCuboid) fits a cuboid\n"
    "around a clicked point of a frame's PCD. Its private parameters are config/cuboids.yaml's (the\n"
    "click:, points: and lshape: sections count; docs/labelling.md); a misspelt one stops it at\n"
    "start-up, naming the known ones. Needs a ROS master.\n"
    "\n"
    "Exit status: 0 shut down, 1 bad parameters at start-up.\n";

int main(int argc, char** argv) {
  if (granular_ros::answerNodeHelp(argc, argv, kHelp)) {
    return 0;
  }
  ros::init(argc, argv, "fit_cuboid_server");
  ros::NodeHandle node;
  ros::NodeHandle private_node("~");
  std::optional<FitCuboidServer> server;
  try {
    server.emplace(node, private_node);
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("fit_cuboid_server: " << error.what());
    return 1;
  }
  ros::spin();
  return 0;
}
