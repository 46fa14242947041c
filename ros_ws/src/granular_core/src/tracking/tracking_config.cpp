#include "granular_core/tracking/tracking_config.h"

namespace granular {

void validate(const TrackingConfig& config) { config::validateFields(config); }

}  // namespace granular
