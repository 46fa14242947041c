// report 8.1: pcl::IterativeClosestPoint (SVD), reused per model and thread.
#include <pcl/registration/icp.h>

#include "icp_common.h"

namespace granular {

std::unique_ptr<RegistrationMethodImpl> prepareIcp(const IcpClassifierConfig& config,
                                                   const PreparedModels& models) {
  using Icp = icp_detail::ReusableIcp<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>;
  return std::make_unique<icp_detail::IcpMethod<Icp>>(config, models);
}

}  // namespace granular
