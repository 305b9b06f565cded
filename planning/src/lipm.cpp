#include "navaid/planning/lipm.hpp"

#include <cmath>

namespace navaid::planning {

double LipmParams::time_constant() const { return std::sqrt(com_height_m / gravity); }

LipmState lipm_propagate(const LipmParams& p, const LipmState& s0, double t) {
  const double tc = p.time_constant();
  const double c = std::cosh(t / tc);
  const double s = std::sinh(t / tc);
  return LipmState{s0.r * c + tc * s0.v * s, s0.r * (s / tc) + s0.v * c};
}

Vec2 lfpc_foot_offset(const LfpcInput& u, Foot foot, double b, const Vec2& com_velocity) {
  const double ct = std::cos(u.direction_rad);
  const double st = std::sin(u.direction_rad);
  const double w = foot == Foot::kRight ? -u.step_width_m : u.step_width_m;
  // R(theta) (-a_l, w): eq. 7's four lines are its x and y for the right (w = -a_w) and left foot.
  return Vec2(-u.step_length_m * ct - w * st, -u.step_length_m * st + w * ct) + b * com_velocity;
}

GainInterval lfpc_stable_gains(const LipmParams& p) {
  const double tc = p.time_constant();
  const double c = std::cosh(p.support_time_s / tc);
  const double s = std::sinh(p.support_time_s / tc);
  return GainInterval{tc * (c - 1.0) / s, tc * (c + 1.0) / s};
}

double lfpc_steady_speed(const LipmParams& p, double step_length_m, double b) {
  const double tc = p.time_constant();
  const double c = std::cosh(p.support_time_s / tc);
  const double k = std::sinh(p.support_time_s / tc) / tc;
  return k * step_length_m / (1.0 - c + b * k);
}

LipmStepTable lipm_step_table(const LipmParams& p, int n_samples) {
  LipmStepTable table;
  table.time_constant = p.time_constant();
  for (int i = 1; i <= n_samples; ++i) {
    const double t = p.support_time_s * static_cast<double>(i) / static_cast<double>(n_samples);
    table.cosh_.push_back(std::cosh(t / table.time_constant));
    table.sinh_.push_back(std::sinh(t / table.time_constant));
  }
  return table;
}

WalkerState lfpc_step(const LipmStepTable& table, double b, const WalkerState& s, const LfpcInput& u,
                      std::vector<Vec2>* samples) {
  const Vec2 foot = s.com + lfpc_foot_offset(u, s.next, b, s.velocity);
  const Vec2 r0 = s.com - foot;
  const double tc = table.time_constant;
  const std::size_t n = table.cosh_.size();
  if (samples != nullptr) {
    samples->resize(n);
    for (std::size_t i = 0; i < n; ++i) (*samples)[i] = foot + r0 * table.cosh_[i] + tc * s.velocity * table.sinh_[i];
  }
  const double c = table.cosh_[n - 1];
  const double sh = table.sinh_[n - 1];
  return WalkerState{foot + r0 * c + tc * s.velocity * sh, r0 * (sh / tc) + s.velocity * c, foot, other(s.next),
                     u.direction_rad};
}

}  // namespace navaid::planning
