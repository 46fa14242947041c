// bench_registration: the report's registration loop against granular's, on the same objects
// and models in one process, one after the other (its options and comparisons:
// bench_registration.h).
#include <stdexcept>
#include <string>

#include <granular_core/registration/registration_config.h>
#include <pcl/console/print.h>

#include "bench_registration.h"
#include "granular_ros/config_file.h"
#include "granular_ros/presets.h"

int main(int argc, char** argv) {
  granular_ros::BenchRegistrationOptions options;
  granular::RegistrationClassifierConfig config;
  granular_ros::Tool tool("bench_registration");
  options.declareIn(tool);
  const auto configure = [&] {
    config = granular_ros::resolvePreset(options.config_file, options.preset);
    for (const std::string& method : options.methods) {
      granular_ros::parseChoice<granular::RegistrationMethod>("--methods", method);
    }
  };
  return tool.run(argc, argv, configure, [&] {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    if (options.end_to_end ? !granular_ros::compareWholeRuns(options, config)
                           : !granular_ros::compareLoops(options, config)) {
      throw std::runtime_error(options.end_to_end
                                   ? "the two whole runs predict differently (ICP or NDT)"
                                   : "the two loops predict differently (ICP or NDT)");
    }
  });
}
