#pragma once
// IMU preintegration between two keyframes i and j (body frame B = IMU frame).
//
// With a_m, w_m the measured specific force and rate, b_a, b_g the biases and R_i the orientation
// at t_i, the preintegrated measurements are
//   gamma_ij = R_i^T R_j,
//   beta_ij  = int_{t_i}^{t_j} R_i^T R(t) (a_m - b_a) dt,
//   alpha_ij = int int R_i^T R(t) (a_m - b_a) dt^2,
// so that, with g_W = (0, 0, -9.81) and dt = t_j - t_i,
//   R_i^T (p_j - p_i - v_i dt - g_W dt^2 / 2) = alpha_ij,
//   R_i^T (v_j - v_i - g_W dt)                 = beta_ij,
//   R_i^T R_j                                   = gamma_ij.
//
// Integration is mid-point between consecutive samples k, k+1 (h = t_{k+1} - t_k):
//   w = (w_k + w_{k+1}) / 2 - b_g,  gamma_{k+1} = gamma_k Exp(w h),
//   a = (gamma_k (a_k - b_a) + gamma_{k+1} (a_{k+1} - b_a)) / 2,
//   alpha_{k+1} = alpha_k + beta_k h + a h^2 / 2,  beta_{k+1} = beta_k + a h.
//
// Error state (the order of StateEstimate's covariance and of the IMU residual):
//   [dtheta (gamma = gamma_hat Exp(dtheta)), dalpha, dbeta, db_g, db_a].
// The step's exact Jacobian F (w.r.t. error state and bias) is accumulated for the bias Jacobians;
// the covariance follows P <- F P F^T + G Q G^T with, per step, one white rate noise and one white
// specific-force noise of variance density^2 / h (the mid-point average of two samples whose
// noise is shared with the neighbouring steps integrates like one continuous-time white noise:
// variance density^2 h per step, Kalibr's convention; for h = 1 / rate the per-sample sigma is
// density * sqrt(rate), as simulation::ImuModel draws it) and bias random walks of variance
// random_walk^2 h.
//
// First-order bias correction for a bias estimate b = b_lin + db:
//   alpha ~ alpha_hat + J_alpha_bg db_g + J_alpha_ba db_a,  beta likewise,
//   gamma ~ gamma_hat Exp(J_gamma_bg db_g).
// When |db| grows past a threshold, repropagate() integrates the stored samples again at the new
// linearization bias.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/core/time.hpp"

namespace navaid::estimation {

/// Continuous-time IMU noise in Kalibr units.
struct ImuNoise {
  double gyro_noise_density = 0;   ///< [rad/s/sqrt(Hz)]
  double accel_noise_density = 0;  ///< [m/s^2/sqrt(Hz)]
  double gyro_random_walk = 0;     ///< [rad/s^2/sqrt(Hz)]
  double accel_random_walk = 0;    ///< [m/s^3/sqrt(Hz)]
  /// A step between two samples longer than this is a gap in the IMU stream (0: none is). It is
  /// bridged in at least two sub-steps of at most half this length with the densities below in place of the sensor's:
  /// the samples on either side say little about the rotation and acceleration in between, and
  /// one long step alone would leave the covariance singular (position and velocity both driven
  /// by the same three force errors).
  double max_sample_gap_s = 0;
  double gap_gyro_density = 0.5;   ///< [rad/s/sqrt(Hz)] the walker's turning, unmeasured
  double gap_accel_density = 2.0;  ///< [m/s^2/sqrt(Hz)] the walker's acceleration, unmeasured

  static ImuNoise from(const ImuCalibration& calibration);
};

/// Throws ConfigError when a density is negative or not finite.
void validate(const ImuNoise& noise, const std::string& source = "imu_noise");

/// Position in the error state / IMU residual.
enum ImuErrorIndex : int { kTheta = 0, kAlpha = 3, kBeta = 6, kBiasGyro = 9, kBiasAccel = 12 };

/// The samples of a time-sorted `stream` that cover [t_begin, t_end]: a sample at t_begin, the
/// samples strictly inside, a sample at t_end. An end that falls between two samples gets a sample
/// linearly interpolated between them (keyframe times rarely hit the IMU grid). Throws Error when
/// the stream does not cover the interval, is not strictly increasing in time, lacks gyro data,
/// or when t_end <= t_begin. With `raw_step_s`, element m (m >= 1) receives the length of the
/// stream interval that holds the step from sample m-1 to m (element 0 is 0): an interpolated
/// step inside a gap is short, but the stream said nothing over the whole gap.
std::vector<ImuSample> imu_samples_between(const std::vector<ImuSample>& stream, Timestamp t_begin,
                                           Timestamp t_end, std::vector<double>* raw_step_s = nullptr);

class ImuPreintegration {
 public:
  /// Empty preintegration at linearization biases b_g, b_a. Validates `noise`.
  ImuPreintegration(const ImuNoise& noise, const Vec3& b_g, const Vec3& b_a);

  /// Preintegrates imu_samples_between(stream, t_i, t_j).
  static ImuPreintegration between(const std::vector<ImuSample>& stream, Timestamp t_i, Timestamp t_j,
                                   const ImuNoise& noise, const Vec3& b_g, const Vec3& b_a);

  /// Appends a sample; the first one sets t_i. Throws Error unless t is strictly after the last
  /// sample and the sample has gyro data. `raw_step_s` is the length of the stream interval this
  /// step lies in (0: the step itself); a step inside a gap longer than
  /// ImuNoise::max_sample_gap_s is bridged.
  void add(const ImuSample& sample, double raw_step_s = 0);

  /// Integrates all samples again at new linearization biases.
  void repropagate(const Vec3& b_g, const Vec3& b_a);
  /// repropagate() when |b_g - b_g_lin| > gyro_threshold or |b_a - b_a_lin| > accel_threshold;
  /// returns whether it did. Call between solves, never while Ceres evaluates factors.
  bool repropagate_if_needed(const Vec3& b_g, const Vec3& b_a, double gyro_threshold, double accel_threshold);

  Timestamp start_time() const;
  Timestamp end_time() const;
  double duration_s() const { return dt_; }  ///< t_j - t_i [s]
  const std::vector<ImuSample>& samples() const { return samples_; }

  const Quat& delta_q() const { return gamma_; }
  const Vec3& delta_p() const { return alpha_; }
  const Vec3& delta_v() const { return beta_; }
  const Vec3& linearization_gyro_bias() const { return b_g_; }
  const Vec3& linearization_accel_bias() const { return b_a_; }

  /// Covariance of the error state [dtheta, dalpha, dbeta, db_g, db_a] (15 x 15).
  const Mat15& covariance() const { return P_; }
  /// Jacobian of the preintegrated values w.r.t. the linearization biases (15 x 15: rows as the
  /// error state; columns 9..14 are the gyro and accel bias; columns 0..8 hold the state
  /// transition from t_i, identity at start).
  const Mat15& jacobian() const { return J_; }
  Mat3 d_theta_d_bg() const { return J_.block<3, 3>(kTheta, kBiasGyro); }
  Mat3 d_alpha_d_bg() const { return J_.block<3, 3>(kAlpha, kBiasGyro); }
  Mat3 d_alpha_d_ba() const { return J_.block<3, 3>(kAlpha, kBiasAccel); }
  Mat3 d_beta_d_bg() const { return J_.block<3, 3>(kBeta, kBiasGyro); }
  Mat3 d_beta_d_ba() const { return J_.block<3, 3>(kBeta, kBiasAccel); }

  /// First-order bias-corrected preintegrated values for bias estimates b_g, b_a.
  Quat corrected_delta_q(const Vec3& b_g) const;
  Vec3 corrected_delta_p(const Vec3& b_g, const Vec3& b_a) const;
  Vec3 corrected_delta_v(const Vec3& b_g, const Vec3& b_a) const;

  /// State at t_j from the state at t_i (first-order bias correction at the given biases).
  void predict(const SE3& T_W_Bi, const Vec3& v_i, const Vec3& b_g, const Vec3& b_a, SE3* T_W_Bj,
               Vec3* v_j) const;

 private:
  void reset_integration();
  void integrate_step(const ImuSample& s0, const ImuSample& s1, double raw_step_s);
  /// One mid-point step with white-noise densities ng (rate) and na (specific force).
  void integrate_substep(const ImuSample& s0, const ImuSample& s1, double ng, double na);

  ImuNoise noise_;
  Vec3 b_g_, b_a_;
  std::vector<ImuSample> samples_;
  std::vector<double> raw_step_s_;  ///< per sample, as given to add()
  double dt_ = 0;
  Quat gamma_ = Quat::Identity();
  Vec3 alpha_ = Vec3::Zero(), beta_ = Vec3::Zero();
  Mat15 J_ = Mat15::Identity();
  Mat15 P_ = Mat15::Zero();
};

}  // namespace navaid::estimation
