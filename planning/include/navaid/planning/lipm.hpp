#pragma once
// The walking model of the Smart Cane's walking-path generator (seed smart-cane-biped-walking-
// path-generation, §IV-C): the Linear Inverted Pendulum (LIPM, eq. 2-4) moves the centre of mass
// (CoM) over the support foot during one step, the Linear Foot Placement Controller (LFPC,
// eq. 5-8) picks where the next foot lands from the CoM velocity at touchdown.
//
// Conventions (the paper leaves them implicit; these are the ones under which its stability
// bound eq. 8 holds):
//   - LIPM: r = p_CoM - p_foot, both axes decoupled (eq. 4): r'' = (g / h) r, so with
//     T_c = sqrt(h / g), r(t) = r0 cosh(t/T_c) + T_c v0 sinh(t/T_c) and
//     v(t) = (r0 / T_c) sinh(t/T_c) + v0 cosh(t/T_c). The paper's eq. 3 prints the velocity's first
//     term as x(0) sinh(t/T_c), without the 1/T_c that the derivative (and its units) require.
//   - LFPC eq. 7: the new foot relative to the CoM at touchdown, in the world frame:
//     p_foot - p_CoM = R(theta) (-a_l, -/+ a_w) + b v   (right foot: -a_w, left: +a_w),
//     theta the walking direction, v the CoM velocity. Then the step's map of the forward velocity
//     is v' = c v + (s / T_c)(a_l - b v) (c = cosh, s = sinh of t_sup / T_c), a contraction exactly
//     when T_c (c - 1) / s < b < T_c (c + 1) / s: eq. 8.
// The paper gives g = 10 m/s^2, b = 0.4, 0.4 <= a_l <= 0.6, 0.1 <= a_w <= 0.2, t_sup = 0.3 s but no
// CoM height h; we take h = 1.0 m (an adult's CoM), for which eq. 8 reads 0.140 < b < 0.716,
// and a_l = 0.5 m settles to 1.92 m/s at touchdown, 0.54 m per step (lfpc_steady_speed).
#include "navaid/mapping/cost_map.hpp"

namespace navaid::planning {

using mapping::Vec2;

struct LipmParams {
  double gravity = 10.0;       ///< g [m/s^2] (the paper's value)
  double com_height_m = 1.0;   ///< h [m] (not in the paper)
  double support_time_s = 0.3; ///< t_sup: duration of one step [s]
  double time_constant() const;  ///< T_c = sqrt(h / g) [s]
};

/// CoM relative to the support foot and its velocity, per axis (eq. 3, both axes by eq. 4).
struct LipmState {
  Vec2 r = Vec2::Zero();  ///< p_CoM - p_foot [m]
  Vec2 v = Vec2::Zero();  ///< CoM velocity [m/s]
};

/// The LIPM's closed-form solution after `t` seconds from `s0` (eq. 3 with the 1/T_c fixed).
LipmState lipm_propagate(const LipmParams& p, const LipmState& s0, double t);

enum class Foot { kLeft, kRight };
inline Foot other(Foot f) { return f == Foot::kLeft ? Foot::kRight : Foot::kLeft; }

/// One step's LFPC input: step length a_l, step width a_w [m] and walking direction theta [rad].
struct LfpcInput {
  double step_length_m = 0.5;
  double step_width_m = 0.15;
  double direction_rad = 0.0;
};

/// Eq. 7: where `foot` lands relative to the CoM at touchdown (world frame), with gain b.
Vec2 lfpc_foot_offset(const LfpcInput& u, Foot foot, double b, const Vec2& com_velocity);

/// Eq. 8: the open interval of LFPC gains b for which the step-to-step velocity map is stable.
struct GainInterval {
  double low = 0.0, high = 0.0;
  bool contains(double b) const { return b > low && b < high; }
};
GainInterval lfpc_stable_gains(const LipmParams& p);

/// The forward CoM speed at touchdown of the periodic gait that input a_l settles to with gain b
/// (the fixed point of the velocity map above): v* = (s/T_c) a_l / (1 - c + b s/T_c).
double lfpc_steady_speed(const LipmParams& p, double step_length_m, double b);

/// One step of the walker: where the CoM is at touchdown (position, velocity), which foot lands
/// next, and where the last foot stands (the support foot of the step that just ended).
struct WalkerState {
  Vec2 com = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  Vec2 support_foot = Vec2::Zero();
  Foot next = Foot::kRight;
  double direction_rad = 0.0;  ///< theta of the last step
};

/// cosh and sinh of t / T_c at the times a step is sampled at: n evenly spaced in (0, t_sup],
/// the last one t_sup (so a search evaluates eq. 3 without transcendental functions).
struct LipmStepTable {
  double time_constant = 0.0;
  std::vector<double> cosh_, sinh_;
};
LipmStepTable lipm_step_table(const LipmParams& p, int n_samples);

/// updateOneStep() of Alg. 1: the next foot lands by eq. 7 (with u.direction_rad as theta), the
/// CoM swings over it for t_sup by eq. 3-4. `samples` (if not null) receives the CoM positions at
/// the table's times (the motion primitive's CoM path; the last one is the new CoM).
WalkerState lfpc_step(const LipmStepTable& table, double b, const WalkerState& s, const LfpcInput& u,
                      std::vector<Vec2>* samples = nullptr);

}  // namespace navaid::planning
