#include "granular_ros/node_parameters.h"

#include <iostream>
#include <stdexcept>

#include <xmlrpcpp/XmlRpcValue.h>

#include "granular_ros/command_line.h"

namespace granular_ros {
namespace {

granular::config::Json toJson(XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return static_cast<bool>(value);
    case XmlRpc::XmlRpcValue::TypeInt:
      return static_cast<int>(value);
    case XmlRpc::XmlRpcValue::TypeDouble:
      return static_cast<double>(value);
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(value);
    case XmlRpc::XmlRpcValue::TypeArray: {
      granular::config::Json json = granular::config::Json::array();
      for (int i = 0; i < value.size(); ++i) {
        json.push_back(toJson(value[i]));
      }
      return json;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      granular::config::Json json = granular::config::Json::object();
      for (auto& [key, member] : value) {
        json[key] = toJson(member);
      }
      return json;
    }
    default:
      return nullptr;
  }
}

}  // namespace

bool answerNodeHelp(int argc, char** argv, const char* help) {
  if (!asksForHelp(argc, argv)) {
    return false;
  }
  std::cout << help;
  return true;
}

granular::config::Json parametersOf(const ros::NodeHandle& node) {
  XmlRpc::XmlRpcValue parameters;
  if (!node.getParam(node.getNamespace(), parameters)) {
    return granular::config::Json::object();
  }
  return toJson(parameters);
}

}  // namespace granular_ros
