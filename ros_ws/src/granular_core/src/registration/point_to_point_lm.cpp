// ICP-NL's least-squares step with analytic Jacobians (point_to_point_lm.h). The normal
// equations and the cost of the point-to-point sum depend on the pairs only through their
// moments (count, centroids, second moments), so one pass over the pairs gathers those and
// every Levenberg-Marquardt iteration after it costs the same whatever the number of pairs.
#include "granular_core/registration/point_to_point_lm.h"

#include <algorithm>
#include <cstddef>

namespace granular {
namespace {

constexpr int kMaxIterations = 100;
constexpr double kStepTolerance = 1e-10;  // m and rad
constexpr double kInitialDamping = 1e-4;  // relative to the normal matrix's diagonal
constexpr double kMaxDamping = 1e12;

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The vector of the antisymmetric part of `a`: sum over pairs of a x b when a = sum a b^T.
Eigen::Vector3d crossOf(const Eigen::Matrix3d& a) {
  return Eigen::Vector3d(a(1, 2) - a(2, 1), a(2, 0) - a(0, 2), a(0, 1) - a(1, 0));
}

// The pairs, centred on their centroids (P = p - mean p, Q = q - mean q), by their moments.
struct Moments {
  double count = 0.0;
  Eigen::Matrix3d source_second = Eigen::Matrix3d::Zero();  // sum P P^T
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();          // sum P Q^T
  double source_square = 0.0;                                // sum |P|^2
  double target_square = 0.0;                                // sum |Q|^2

  // sum |R P + t - Q|^2 (the sums of P and Q are zero).
  double cost(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& shift) const {
    return source_square + target_square + count * shift.squaredNorm() -
           2.0 * (rotation * cross).trace();
  }
};

}  // namespace

Eigen::Isometry3d pointToPointLm(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target) {
  if (source.empty()) {
    return Eigen::Isometry3d::Identity();
  }
  Eigen::Vector3d source_mean = Eigen::Vector3d::Zero(), target_mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < source.size(); ++i) {
    source_mean += source[i];
    target_mean += target[i];
  }
  Moments moments;
  moments.count = static_cast<double>(source.size());
  source_mean /= moments.count;
  target_mean /= moments.count;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3d p = source[i] - source_mean, q = target[i] - target_mean;
    moments.source_second.noalias() += p * p.transpose();
    moments.cross.noalias() += p * q.transpose();
    moments.source_square += p.squaredNorm();
    moments.target_square += q.squaredNorm();
  }

  // Levenberg-Marquardt on the centred pairs from the motion the identity gives them (a
  // shift of the centroids' difference), each step a left increment (t, w) that moves a
  // point p' = R P + t by t + w x p'. Residual r = p' - Q, Jacobian [I, -[p']x]:
  // J^T J = [[n I, -[S]x], [[S]x, tr(N) I - N]] and J^T r = [S, -(sum p' x Q)], with
  // S = sum p' = n t, N = sum p' p'^T = R M R^T + n t t^T and sum p' x Q = cross(R C), where
  // M and C are the moments.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d shift = source_mean - target_mean;
  double current = moments.cost(rotation, shift);
  double damping = kInitialDamping;
  const double n = moments.count;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const Eigen::Vector3d sum = n * shift;
    const Eigen::Matrix3d spread =
        rotation * moments.source_second * rotation.transpose() + n * shift * shift.transpose();
    Matrix6 normal;
    normal << n * Eigen::Matrix3d::Identity(), -skew(sum), skew(sum),
        spread.trace() * Eigen::Matrix3d::Identity() - spread;
    Vector6 gradient;
    gradient << sum, -crossOf(rotation * moments.cross);
    const Vector6 diagonal = normal.diagonal().cwiseMax(1e-12);
    bool improved = false;
    Vector6 step;
    while (damping <= kMaxDamping) {
      Matrix6 damped = normal;
      damped.diagonal() += damping * diagonal;
      step = -damped.ldlt().solve(gradient);
      const double angle = step.tail<3>().norm();
      const Eigen::Matrix3d turn =
          angle > 0.0 ? Eigen::AngleAxisd(angle, step.tail<3>() / angle).toRotationMatrix()
                      : Eigen::Matrix3d::Identity();
      const Eigen::Matrix3d candidate_rotation = turn * rotation;
      const Eigen::Vector3d candidate_shift = turn * shift + step.head<3>();
      const double candidate_cost = moments.cost(candidate_rotation, candidate_shift);
      if (candidate_cost <= current) {
        rotation = candidate_rotation;
        shift = candidate_shift;
        current = candidate_cost;
        damping = std::max(damping / 10.0, 1e-12);
        improved = true;
        break;
      }
      damping *= 10.0;
    }
    if (!improved || step.norm() < kStepTolerance) {
      break;
    }
  }
  // q = R (p - mean p) + t + mean q.
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = rotation;
  motion.translation() = shift + target_mean - rotation * source_mean;
  return motion;
}

}  // namespace granular
