// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Kalman filter of a point moving at constant velocity, observed in position.

#include <Eigen/Core>

namespace underwater_stereo {

/// State [position; velocity] in one fixed frame [m, m/s]; white-noise acceleration drives the velocity.
class ConstantVelocityFilter {
 public:
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;

  /// At the origin with unit covariance (to be assigned).
  ConstantVelocityFilter() = default;
  /// Starts at `position` with covariance `position_covariance` and zero velocity of standard deviation
  /// `speed_sigma_mps` per axis.
  ConstantVelocityFilter(const Eigen::Vector3d& position, const Eigen::Matrix3d& position_covariance,
                         double speed_sigma_mps);

  /// Moves the state `dt_s` ahead (dt_s >= 0); `acceleration_sigma` [m/s^2] sets the process noise.
  void predict(double dt_s, double acceleration_sigma);
  /// Like predict(), but the position stays where it is (the velocity is kept, not applied); the uncertainty
  /// grows as with predict().
  void hold(double dt_s, double acceleration_sigma);
  /// Squared Mahalanobis distance of the velocity from zero: how sure the filter is that the point moves.
  double velocitySignificance() const;
  /// Squared Mahalanobis distance of a position measurement `z` with covariance `r` from the prediction.
  double mahalanobis2(const Eigen::Vector3d& z, const Eigen::Matrix3d& r) const;
  /// Fuses a position measurement (Joseph form, so the covariance stays symmetric positive definite).
  void update(const Eigen::Vector3d& z, const Eigen::Matrix3d& r);

  Eigen::Vector3d position() const { return x_.head<3>(); }
  Eigen::Vector3d velocity() const { return x_.tail<3>(); }
  Eigen::Matrix3d positionCovariance() const { return p_.topLeftCorner<3, 3>(); }
  Eigen::Matrix3d velocityCovariance() const { return p_.bottomRightCorner<3, 3>(); }

 private:
  Vector6 x_ = Vector6::Zero();
  Matrix6 p_ = Matrix6::Identity();
};

}  // namespace underwater_stereo
