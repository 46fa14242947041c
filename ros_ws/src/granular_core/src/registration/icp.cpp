// report 8.1: ICP with PCL's SVD (Umeyama) step, PCL's loop written out (point_to_point_icp.h).
#include "point_to_point_icp.h"

namespace granular {

std::unique_ptr<RegistrationMethodImpl> prepareIcp(const IcpClassifierConfig& config,
                                                   const PreparedModels& models) {
  return std::make_unique<icp_detail::PointToPointMethod<icp_detail::SvdStep>>(config, models);
}

}  // namespace granular
