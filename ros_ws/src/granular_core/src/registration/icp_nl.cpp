// report 8.2: pcl::IterativeClosestPointNonLinear (Levenberg-Marquardt), reused per model and
// thread.
#include <pcl/registration/icp_nl.h>

#include "icp_common.h"

namespace granular {

std::unique_ptr<RegistrationMethodImpl> prepareIcpNl(const IcpClassifierConfig& config,
                                                     const PreparedModels& models) {
  using IcpNl =
      icp_detail::ReusableIcp<pcl::IterativeClosestPointNonLinear<pcl::PointXYZ, pcl::PointXYZ>>;
  return std::make_unique<icp_detail::IcpMethod<IcpNl>>(config, models);
}

}  // namespace granular
