#pragma once
// IMU measurement model for the simulator: exact kinematics plus Kalibr-style noise.
//
//   gyro  = M_g omega_I + b_g + n_g
//   accel = M_a R_W_I^T (a_W_I - g_W) + b_a + n_a,   g_W = (0, 0, -9.81)
//
// where M_g, M_a are scale/misalignment matrices (identity by default: an ideal, calibrated IMU;
// diagonal = scale factors, off-diagonal = axis misalignment), I is the IMU frame (calibration T_B_I; identity when the body is the IMU, in which case
// omega_I = omega_B and a_W_I = a_W). Continuous-time densities become discrete white noise
// sigma = density * sqrt(rate_hz); biases follow a random walk, each step sigma = random_walk *
// sqrt(dt) with dt the time since the previous measure() call. Randomness comes from one
// std::mt19937_64 seeded explicitly, so a seed fully determines the stream.
#include <cstdint>
#include <random>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/time.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::simulation {

/// A mechanical shock (a cane striking a kerb, the phone knocked): this specific force [m/s^2, IMU
/// frame] added to every accelerometer sample in [begin, end), beyond what the motion explains.
struct ImuShock {
  Timestamp begin = 0;
  Timestamp end = 0;
  Vec3 accel_I = Vec3::Zero();
};

struct ImuModelOptions {
  std::uint64_t seed = 0;
  bool white_noise = true;  ///< add n_g, n_a
  bool bias_walk = true;    ///< let b_g, b_a random-walk (otherwise they stay at the initial values)
  Vec3 initial_gyro_bias = Vec3::Zero();   ///< [rad/s]
  Vec3 initial_accel_bias = Vec3::Zero();  ///< [m/s^2]
  Mat3 gyro_scale_misalignment = Mat3::Identity();   ///< M_g, within 0.2 of I entry-wise
  Mat3 accel_scale_misalignment = Mat3::Identity();  ///< M_a, within 0.2 of I entry-wise
  std::vector<ImuShock> shocks;
};

class ImuModel {
 public:
  /// Throws ConfigError when rate_hz <= 0 or a noise density is negative.
  explicit ImuModel(const ImuCalibration& calibration, const ImuModelOptions& options = {});

  /// Measurement at time t of a body in state `body` (B frame kinematics). Calls must come in
  /// non-decreasing time; the biases are advanced to t first. Throws std::invalid_argument
  /// when t goes backwards.
  ImuSample measure(const KinematicState& body, Timestamp t);

  /// The true biases at the time of the last measure() call (ground truth for estimators).
  const Vec3& gyro_bias() const { return b_g_; }
  const Vec3& accel_bias() const { return b_a_; }

  double gyro_noise_sigma() const;   ///< discrete white-noise sigma per sample [rad/s]
  double accel_noise_sigma() const;  ///< [m/s^2]
  const ImuCalibration& calibration() const { return calib_; }

 private:
  Vec3 gaussian3(double sigma);

  ImuCalibration calib_;
  ImuModelOptions options_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Vec3 b_g_, b_a_;
  bool has_last_ = false;
  Timestamp last_t_ = 0;
};

/// IMU samples and the matching ground truth (body pose, body velocity, true IMU biases).
struct SimulatedImuStream {
  std::vector<ImuSample> samples;
  std::vector<GroundTruthState> ground_truth;
};

/// Samples at the model's rate over trajectory times [t_begin_s, t_end_s] (both ends included
/// when on the grid). Timestamps are epoch + seconds_to_ns(t_begin_s) + round(k / rate) in ns;
/// the trajectory is evaluated at exactly those (rounded) times.
SimulatedImuStream simulate_imu_stream(const WalkerTrajectory& trajectory, ImuModel& model, double t_begin_s,
                                       double t_end_s, Timestamp epoch = 0);

}  // namespace navaid::simulation
