#include "navaid/simulation/recorded_motion.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

RecordedMotion::RecordedMotion(std::vector<GroundTruthState> samples) : samples_(std::move(samples)) {
  if (samples_.size() < 2) throw Error("RecordedMotion: needs at least 2 ground-truth states, got " + std::to_string(samples_.size()));
  for (std::size_t i = 1; i < samples_.size(); ++i)
    if (!(samples_[i].t > samples_[i - 1].t))
      throw Error("RecordedMotion: ground-truth times must strictly increase (state " + std::to_string(i) + ")");
}

SE3 RecordedMotion::pose_at(Timestamp t) const {
  if (t < begin() || t > end())
    throw Error("RecordedMotion: time " + std::to_string(t) + " ns is outside the ground truth's span");
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), t,
                                      [](const GroundTruthState& s, Timestamp x) { return s.t < x; });
  if (after->t == t) return after->T_W_B;
  const GroundTruthState& a = *(after - 1);
  const GroundTruthState& b = *after;
  const double h = ns_to_seconds(b.t - a.t);
  const double x = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  const Vec3& p0 = a.T_W_B.t;
  const Vec3& p1 = b.T_W_B.t;
  Vec3 p = (1.0 - x) * p0 + x * p1;
  if (a.v_W && b.v_W) {  // cubic Hermite: matches both positions and both velocities
    const double h00 = 2 * x * x * x - 3 * x * x + 1, h10 = x * x * x - 2 * x * x + x;
    const double h01 = -2 * x * x * x + 3 * x * x, h11 = x * x * x - x * x;
    p = h00 * p0 + h10 * h * *a.v_W + h01 * p1 + h11 * h * *b.v_W;
  }
  return SE3(a.T_W_B.q.slerp(x, b.T_W_B.q).normalized(), p);
}

AxisAlignedBox RecordedMotion::bounds() const {
  AxisAlignedBox box;
  for (const auto& s : samples_) box.extend(s.T_W_B.t);
  return box;
}

}  // namespace navaid::simulation
