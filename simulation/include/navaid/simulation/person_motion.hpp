#pragma once
// The body of a simulated person walking in closed loop: the next motion depends on what the
// person decides now (a heading or a turn rate to follow, a speed), not on a path planned in
// advance (walker_trajectory.hpp is the open-loop counterpart).
//
// State: ground position p (x, y) in W, walking heading psi, forward speed u, yaw rate r. Over one
// step the person's forward acceleration and yaw acceleration are constant (first-order lags toward
// the commanded speed and turn rate, both bounded), so u, r and psi are exact polynomials in time and
// the IMU sees the accelerations the pose really has: a_W = du/dt t + u r n (t the heading, n its
// left normal) plus the gait's vertical bob. The rig on the body may yaw-scan (a cane's sweep,
// Mount::scan_amplitude_rad), which turns B but does not move it. A person walking without sight
// veers: the heading they hold drifts from the one they mean, as a seeded Ornstein-Uhlenbeck
// error that grows only while they walk and is cleared when they take a new direction from a cue.
//
// Frames as the simulator's: W z up; B x forward, y left, z up; R_W_B = Rz(psi + scan(t)).
#include <cstdint>
#include <random>

#include "navaid/core/geometry.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation {

struct PersonMotionConfig {
  double mount_height_m = 1.0;        ///< B above the ground
  double ground_z_m = 0.0;
  double speed_time_constant_s = 0.4; ///< lag of the speed toward its command
  double max_acceleration_mps2 = 1.0; ///< |du/dt| bound
  double heading_gain_per_s = 3.0;    ///< turn rate per radian of heading error
  double max_turn_rate_rad_s = 1.6;   ///< |r| bound (about 90 deg/s)
  double turn_time_constant_s = 0.08; ///< lag of the turn rate toward its command
  double max_yaw_acceleration_rad_s2 = 8.0;
  double step_length_m = 0.65;        ///< the gait's step: bob frequency = u / step length
  double bob_amplitude_m = 0.02;      ///< vertical bob of B while walking
  double scan_amplitude_rad = 0.0;    ///< yaw scan of the rig (cane sweep), 0 for none
  double scan_period_s = 1.2;
  /// Veer: the held heading's error random-walks with this density [rad per sqrt(s) walked],
  /// pulled back toward zero with veer_time_constant_s; 0: none.
  double veer_sigma = 0.0;
  double veer_time_constant_s = 10.0;
};

/// Throws ConfigError naming the field when a value is out of range.
void validate(const PersonMotionConfig& config);

/// What the person does now: follow a heading, or a turn rate (a steering wheel's pull); walk at
/// a speed (0: stand).
struct MotionCommand {
  double speed_mps = 0.0;
  bool follow_heading = true;
  double heading_rad = 0.0;    ///< walking heading in W (follow_heading)
  double turn_rate_rad_s = 0;  ///< yaw rate to hold (otherwise)
  bool new_direction = false;  ///< taken from a cue just now: the veer starts afresh
};

class PersonMotion {
 public:
  /// Starts standing at `position` facing `heading_rad`. The drift's noise comes from `seed`.
  PersonMotion(const PersonMotionConfig& config, const Vec2& position, double heading_rad, std::uint64_t seed);

  /// Advances by dt > 0 [s] under `command` (held over the step). Throws std::invalid_argument for
  /// dt <= 0.
  void step(const MotionCommand& command, double dt);
  /// The body ran into something: back at `position` (where the step began), standing. The stop
  /// is an impact: state() carries the deceleration that takes the walking velocity to zero over
  /// the last step until the next step(), so an IMU sampled from it feels the bump (without it
  /// the IMU kept walking while the camera stood, and the estimator failed at every bump).
  void halt_at(const Vec2& position);

  /// Body state now (exact derivatives of the motion over the last step, gait and scan included).
  KinematicState state() const;

  /// The person takes a new direction from a cue: the veer built up so far is gone.
  void clear_veer() { veer_ = 0; }
  double veer() const { return veer_; }

  double time() const { return t_; }
  const Vec2& position() const { return p_; }
  double heading() const { return psi_; }  ///< walking heading (without the rig's scan)
  double speed() const { return u_; }
  double yaw_rate() const { return r_; }
  double yaw_acceleration() const { return dr_; }  ///< over the last step
  double distance_walked() const { return walked_; }
  const PersonMotionConfig& config() const { return config_; }

 private:
  PersonMotionConfig config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  double t_ = 0;
  Vec2 p_;
  double psi_ = 0, u_ = 0, r_ = 0;
  double du_ = 0, dr_ = 0;        // accelerations over the last step
  double last_dt_ = 0;            // the last step's length [s]
  Vec2 impact_a_ = Vec2::Zero();  // the bump's deceleration, until the next step [m/s^2]
  double veer_ = 0;               // heading error of the held direction [rad]
  double gait_phase_ = 0;         // radians, advances at 2 pi u / step length
  double walked_ = 0;
};

}  // namespace navaid::simulation
