#include "navaid/estimation/state_prediction.hpp"

namespace navaid::estimation {

Mat15 state_transition(const ImuPreintegration& pre, const StateEstimate& from) {
  const Mat3 R_i = from.T_W_B.rotation();
  const Mat3 dR = pre.corrected_delta_q(from.b_g).toRotationMatrix();
  const Vec3 dp = pre.corrected_delta_p(from.b_g, from.b_a);
  const Vec3 dv = pre.corrected_delta_v(from.b_g, from.b_a);
  Mat15 F = Mat15::Identity();
  F.block<3, 3>(kTheta, kTheta) = dR.transpose();
  F.block<3, 3>(kTheta, kBiasGyro) = pre.d_theta_d_bg();
  F.block<3, 3>(kAlpha, kTheta) = -R_i * hat(dp);
  F.block<3, 3>(kAlpha, kBeta) = pre.duration_s() * Mat3::Identity();
  F.block<3, 3>(kAlpha, kBiasGyro) = R_i * pre.d_alpha_d_bg();
  F.block<3, 3>(kAlpha, kBiasAccel) = R_i * pre.d_alpha_d_ba();
  F.block<3, 3>(kBeta, kTheta) = -R_i * hat(dv);
  F.block<3, 3>(kBeta, kBiasGyro) = R_i * pre.d_beta_d_bg();
  F.block<3, 3>(kBeta, kBiasAccel) = R_i * pre.d_beta_d_ba();
  return F;
}

StateEstimate predict_state(const StateEstimate& from, Timestamp t, const std::vector<ImuSample>& imu,
                            const ImuNoise& noise) {
  if (t == from.t) return from;
  const ImuPreintegration pre = ImuPreintegration::between(imu, from.t, t, noise, from.b_g, from.b_a);
  StateEstimate to = from;
  to.t = t;
  pre.predict(from.T_W_B, from.v_W, from.b_g, from.b_a, &to.T_W_B, &to.v_W);
  const Mat15 F = state_transition(pre, from);
  Mat15 G = Mat15::Identity();
  G.block<3, 3>(kAlpha, kAlpha) = from.T_W_B.rotation();
  G.block<3, 3>(kBeta, kBeta) = from.T_W_B.rotation();
  to.covariance = F * from.covariance * F.transpose() + G * pre.covariance() * G.transpose();
  to.covariance = 0.5 * (to.covariance + to.covariance.transpose());
  return to;
}

}  // namespace navaid::estimation
