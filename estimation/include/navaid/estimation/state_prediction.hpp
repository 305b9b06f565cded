#pragma once
// The state at a later time from an estimate and the IMU samples between: the propagation that
// lets a consumer act at a camera frame's arrival instead of after the window's solve (as
// VINS-Mono's IMU-rate odometry). Mean by IMU preintegration (imu_preintegration.hpp, biases held),
// covariance to first order in StateEstimate's parametrization:
//   P_j = F P_i F^T + G Q G^T,
//   F: dtheta_j = dR^T dtheta_i + J_theta,bg db_g
//      dp_j     = dp_i + T dv_i - R_i [dp_pre]x dtheta_i + R_i (J_alpha,bg db_g + J_alpha,ba db_a)
//      dv_j     = dv_i - R_i [dv_pre]x dtheta_i + R_i (J_beta,bg db_g + J_beta,ba db_a)
//      biases unchanged;
//   Q: the preintegration's own covariance, G = diag(I, R_i, R_i, I, I) (its position and velocity
//      errors live in the frame of B at t_i).
#include <vector>

#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/estimation/imu_preintegration.hpp"

namespace navaid::estimation {

/// F of the header for a preintegration from the state `from`.
Mat15 state_transition(const ImuPreintegration& preintegration, const StateEstimate& from);

/// The estimate carried to `t` (> from.t) through `imu` (IMU clock = the estimate's clock): pose,
/// velocity and covariance propagated, biases, mode and T_ENU_W kept. Throws Error when the IMU
/// stream does not cover [from.t, t]. t == from.t returns `from`.
StateEstimate predict_state(const StateEstimate& from, Timestamp t, const std::vector<ImuSample>& imu,
                            const ImuNoise& noise);

}  // namespace navaid::estimation
