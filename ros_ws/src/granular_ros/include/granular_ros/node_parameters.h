#pragma once

#include <string>

#include <granular_core/config/fields.h>
#include <ros/node_handle.h>

namespace granular_ros {

/// A node run by hand with -h or --help: prints `help` and returns true, before ros::init,
/// which would wait for a ROS master without end.
bool answerNodeHelp(int argc, char** argv, const char* help);

/// Every parameter under the namespace of `node` (a node's private handle) as JSON.
granular::config::Json parametersOf(const ros::NodeHandle& node);

/// A node's parameters read into `config` through its field list, the same strict reader as
/// the tools' YAML files: a misspelt or unknown parameter, or a value of the wrong type, is a
/// std::runtime_error naming the parameter (~key) and the known ones. Then validate(config).
template <typename Config>
Config readNodeParameters(const ros::NodeHandle& node) {
  Config config;
  try {
    granular::config::readJson(parametersOf(node), config);
  } catch (const granular::config::FieldError& error) {
    throw std::runtime_error("parameter ~" + std::string(error.what()));
  }
  validate(config);
  return config;
}

}  // namespace granular_ros
