#include "navaid/evaluation/enu_position_error.hpp"

#include <algorithm>
#include <cmath>

#include "navaid/evaluation/time_association.hpp"

namespace navaid::evaluation {

namespace {

EnuPositionError accumulate(const std::vector<Vec3>& errors) {
  EnuPositionError out;
  double sq = 0, sq_h = 0, sq_v = 0;
  for (const Vec3& e : errors) {
    sq += e.squaredNorm();
    sq_h += e.head<2>().squaredNorm();
    sq_v += e.z() * e.z();
    out.max_m = std::max(out.max_m, e.norm());
  }
  const double n = static_cast<double>(errors.size());
  out.rmse_m = std::sqrt(sq / n);
  out.horizontal_rmse_m = std::sqrt(sq_h / n);
  out.vertical_rmse_m = std::sqrt(sq_v / n);
  out.poses = errors.size();
  return out;
}

std::vector<Timestamp> times_of(const std::vector<io::StampedPose>& poses) {
  std::vector<Timestamp> t;
  t.reserve(poses.size());
  for (const auto& p : poses) t.push_back(p.t);
  return t;
}

// Fixes paired with the ground-truth antenna position at their time, in fix order.
std::vector<estimation::GpsRegistrationPair> antenna_pairs(const std::vector<GpsFix>& fixes,
                                                           const std::vector<io::StampedPose>& groundtruth_enu,
                                                           const Vec3& lever_arm_B) {
  std::vector<Timestamp> fix_times;
  for (const auto& f : fixes) fix_times.push_back(f.t);
  std::vector<estimation::GpsRegistrationPair> pairs;
  for (const auto& m : associate_by_time(fix_times, times_of(groundtruth_enu)))
    pairs.push_back({fixes[m.est], groundtruth_enu[m.gt].T_W_B * lever_arm_B});
  return pairs;
}

// The registered ground truth's error at each evaluation time: one registration to all fixes
// (batch) or, causally, to the fixes up to that time (redone at each new fix).
std::optional<EnuPositionError> registration_reference(const std::vector<GpsFix>& fixes,
                                                       const std::vector<io::StampedPose>& groundtruth_enu,
                                                       const Vec3& lever_arm_B, const GeodeticOrigin& origin,
                                                       const std::vector<Timestamp>& evaluate_at,
                                                       const estimation::GpsRegistrationOptions& options, bool causal) {
  const auto all = antenna_pairs(fixes, groundtruth_enu, lever_arm_B);
  if (all.empty()) return std::nullopt;
  std::vector<estimation::GpsRegistrationPair> used;
  std::optional<SE3> T;
  std::size_t next = 0;
  const auto take_until = [&](Timestamp t) {
    const std::size_t before = next;
    while (next < all.size() && all[next].fix.t <= t) used.push_back(all[next++]);
    if (next == before) return;
    const estimation::GpsRegistration r = estimation::register_gps_to_world(used, origin, options);
    if (r.registered()) T = r.T_ENU_W();
  };
  if (!causal) take_until(all.back().fix.t);
  std::vector<Vec3> errors;
  for (const auto& m : associate_by_time(evaluate_at, times_of(groundtruth_enu))) {
    if (causal) take_until(evaluate_at[m.est]);
    if (!T) continue;
    const Vec3& p = groundtruth_enu[m.gt].T_W_B.t;
    errors.push_back(*T * p - p);
  }
  if (errors.empty()) return std::nullopt;
  return accumulate(errors);
}

}  // namespace

std::optional<EnuPositionError> enu_position_error(const std::vector<io::StampedPose>& estimate_enu,
                                                   const std::vector<io::StampedPose>& groundtruth_enu) {
  std::vector<Vec3> errors;
  for (const auto& p : associate_poses(estimate_enu, groundtruth_enu)) errors.push_back(p.est.t - p.gt.t);
  if (errors.empty()) return std::nullopt;
  return accumulate(errors);
}

std::optional<EnuPositionError> rigid_registration_reference(const std::vector<GpsFix>& fixes,
                                                             const std::vector<io::StampedPose>& groundtruth_enu,
                                                             const Vec3& lever_arm_B, const GeodeticOrigin& origin,
                                                             const std::vector<Timestamp>& evaluate_at,
                                                             const estimation::GpsRegistrationOptions& options) {
  return registration_reference(fixes, groundtruth_enu, lever_arm_B, origin, evaluate_at, options, false);
}

std::optional<EnuPositionError> causal_registration_reference(const std::vector<GpsFix>& fixes,
                                                              const std::vector<io::StampedPose>& groundtruth_enu,
                                                              const Vec3& lever_arm_B, const GeodeticOrigin& origin,
                                                              const std::vector<Timestamp>& evaluate_at,
                                                              const estimation::GpsRegistrationOptions& options) {
  return registration_reference(fixes, groundtruth_enu, lever_arm_B, origin, evaluate_at, options, true);
}

}  // namespace navaid::evaluation
