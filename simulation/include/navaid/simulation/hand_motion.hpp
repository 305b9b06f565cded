#pragma once
// The hand that holds a hand-held rig (W-ROMA), moved relative to the body of a simulated person
// (person_motion.hpp): reaching toward an object, the hand leaves the chest; the rig's pose, and
// so its IMU, follows the hand.
//
// The hand's offset o from the body's centre is kept in the walking frame (x forward along the
// walking heading psi, y left, z up from the rig's mount height). Each axis moves toward its target
// with a bounded first-order lag on its velocity, the acceleration held constant over a step, so
// o, do/dt and d2o/dt2 are exact polynomials over the step. compose() adds the hand to the body's
// state: with R = Rz(psi), r the walking yaw rate and rdot its derivative,
//   p = p_body + R o,   v = v_body + R (do + r z x o),
//   a = a_body + R (d2o + 2 r z x do + rdot z x o + r^2 z x (z x o)).
// The rig's orientation stays the body's (the wrist holds the camera level with the chest).
#include "navaid/core/config.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation {

struct HandMotionConfig {
  Vec3 rest_offset_m{0.30, 0.0, 0.0};    ///< held before the chest
  Vec3 min_offset_m{0.15, -0.45, -0.60}; ///< forward, left, up from the body's centre at mount height
  Vec3 max_offset_m{0.75, 0.45, 0.30};   ///< an arm's reach
  double speed_mps = 0.25;               ///< the hand's speed toward a new place
  double position_time_constant_s = 0.15;  ///< the approach slows within speed x this of the target
  double velocity_time_constant_s = 0.1;
  double max_acceleration_mps2 = 2.0;
};

/// Keys user.hand.*: speed_mps (0.02, 2], max_acceleration_mps2 (0.1, 20], rest_offset_m,
/// min_offset_m, max_offset_m (3 numbers each, metres; min < rest < max per axis). ConfigError
/// naming the key otherwise.
HandMotionConfig read_hand_motion_config(const Config& config);

class HandMotion {
 public:
  explicit HandMotion(const HandMotionConfig& config);

  /// Where the hand goes next (walking frame), clamped to the reach limits.
  void move_to(const Vec3& offset);
  /// Advances by dt > 0 [s]; std::invalid_argument otherwise.
  void step(double dt);

  const Vec3& offset() const { return o_; }
  const Vec3& target() const { return target_; }
  const Vec3& velocity() const { return v_; }
  const HandMotionConfig& config() const { return config_; }
  /// True when the offset is within `tolerance_m` of the limit along `axis` on the side `sign`.
  bool at_limit(int axis, double sign, double tolerance_m = 0.01) const;

  /// The rig's state with the hand: `body` from PersonMotion::state(), psi its walking heading,
  /// r and rdot its walking yaw rate and yaw acceleration.
  KinematicState compose(const KinematicState& body, double psi, double r, double rdot) const;
  /// The hand's position in W (the rig's origin) for a body at `position` and mount height `z`.
  Vec3 position_W(const Vec2& position, double z, double psi) const;

 private:
  HandMotionConfig config_;
  Vec3 o_, v_ = Vec3::Zero(), a_ = Vec3::Zero(), target_;
};

}  // namespace navaid::simulation
