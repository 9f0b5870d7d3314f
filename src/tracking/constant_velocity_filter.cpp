// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/tracking/constant_velocity_filter.h"

#include <Eigen/Cholesky>

namespace underwater_stereo {

ConstantVelocityFilter::ConstantVelocityFilter(const Eigen::Vector3d& position,
                                               const Eigen::Matrix3d& position_covariance, double speed_sigma_mps) {
  x_.setZero();
  x_.head<3>() = position;
  p_.setZero();
  p_.topLeftCorner<3, 3>() = position_covariance;
  p_.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * speed_sigma_mps * speed_sigma_mps;
}

void ConstantVelocityFilter::predict(double dt_s, double acceleration_sigma) {
  if (dt_s <= 0.0) return;
  Matrix6 f = Matrix6::Identity();
  f.topRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * dt_s;
  const double q = acceleration_sigma * acceleration_sigma;
  const double dt2 = dt_s * dt_s;
  Matrix6 noise;
  noise << Eigen::Matrix3d::Identity() * (q * dt2 * dt2 / 4), Eigen::Matrix3d::Identity() * (q * dt2 * dt_s / 2),
      Eigen::Matrix3d::Identity() * (q * dt2 * dt_s / 2), Eigen::Matrix3d::Identity() * (q * dt2);
  x_ = f * x_;
  p_ = f * p_ * f.transpose() + noise;
}

void ConstantVelocityFilter::hold(double dt_s, double acceleration_sigma) {
  if (dt_s <= 0.0) return;
  const double q = acceleration_sigma * acceleration_sigma;
  // The velocity's own uncertainty enters the position as if it had been applied, so a gate still opens wide
  // enough for a point that did move.
  p_.topLeftCorner<3, 3>() += p_.bottomRightCorner<3, 3>() * (dt_s * dt_s) +
                              Eigen::Matrix3d::Identity() * (q * dt_s * dt_s * dt_s * dt_s / 4);
  p_.bottomRightCorner<3, 3>() += Eigen::Matrix3d::Identity() * (q * dt_s * dt_s);
}

double ConstantVelocityFilter::velocitySignificance() const {
  const Eigen::Vector3d v = x_.tail<3>();
  return v.dot(p_.bottomRightCorner<3, 3>().ldlt().solve(v));
}

double ConstantVelocityFilter::mahalanobis2(const Eigen::Vector3d& z, const Eigen::Matrix3d& r) const {
  const Eigen::Vector3d innovation = z - x_.head<3>();
  const Eigen::Matrix3d s = p_.topLeftCorner<3, 3>() + r;
  return innovation.dot(s.ldlt().solve(innovation));
}

void ConstantVelocityFilter::update(const Eigen::Vector3d& z, const Eigen::Matrix3d& r) {
  const Eigen::Matrix3d s = p_.topLeftCorner<3, 3>() + r;
  // K = P H^T S^-1 with H = [I 0]: P's first three columns.
  const Eigen::Matrix<double, 6, 3> k = s.ldlt().solve(p_.leftCols<3>().transpose()).transpose();
  x_ += k * (z - x_.head<3>());
  Matrix6 i_kh = Matrix6::Identity();
  i_kh.leftCols<3>() -= k;
  p_ = i_kh * p_ * i_kh.transpose() + k * r * k.transpose();
}

}  // namespace underwater_stereo
