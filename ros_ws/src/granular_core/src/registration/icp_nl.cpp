// report 8.2: ICP-NL, PCL's loop written out (point_to_point_icp.h) with its Levenberg-Marquardt
// step (PCL's TransformationEstimationLM: numerical Jacobians, float) replaced by
// pointToPointLm (analytic Jacobians, double) that minimises the same sum. reference.cpp keeps
// PCL's own class and step for the report's loop.
#include "point_to_point_icp.h"

namespace granular {

std::unique_ptr<RegistrationMethodImpl> prepareIcpNl(const IcpClassifierConfig& config,
                                                     const PreparedModels& models) {
  return std::make_unique<icp_detail::PointToPointMethod<icp_detail::AnalyticLmStep>>(config,
                                                                                      models);
}

}  // namespace granular
