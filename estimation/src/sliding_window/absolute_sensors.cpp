// The window's absolute sensors: GPS fixes (joint: registration, then factors with a multipath
// bias per fix; decoupled: re-registration at every fix) and the magnetometer's heading reference.
#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "navaid/core/geodesy.hpp"
#include "navaid/estimation/factors/gauss_markov_factor.hpp"
#include "impl.hpp"

namespace navaid::estimation {

namespace {

/// Covariance of [yaw, t_x, t_y, t_z]; a registration without heights leaves t_z loosely known.
Mat4 alignment_covariance(const GpsRegistration& r) {
  Mat4 P = Mat4::Identity() * kUnregisteredHeightSigma * kUnregisteredHeightSigma;
  const int n = static_cast<int>(r.covariance.rows());
  P.topLeftCorner(n, n) = r.covariance;
  return P;
}

}  // namespace

Vec3 SlidingWindowEstimator::Impl::fix_enu(const GpsFix& fix) const {
  // The registration's eq. 6 conversion, so that factors and registration agree.
  return geodesic_enu({fix}, *origin).front();
}

void SlidingWindowEstimator::Impl::attach_gps(WindowState& s) {
  const Timestamp tolerance = static_cast<Timestamp>(std::llround(cfg.gps_max_time_offset_s * 1e9));
  while (!pending_fixes.empty() && pending_fixes.front().t < s.t - tolerance) pending_fixes.pop_front();  // missed
  if (!pending_fixes.empty() && pending_fixes.front().t <= s.t + tolerance) {
    s.gps = pending_fixes.front();
    pending_fixes.pop_front();
    if (gps_outlier(*s.gps, s)) {
      s.gps.reset();
      ++stats.gps_outliers;
    }
  }
}

bool SlidingWindowEstimator::Impl::gps_outlier(const GpsFix& fix, const WindowState& s) {
  if (cfg.gps_outlier_gate <= 0) return false;
  // T_ENU_W as the window holds it (joint) or as last registered (decoupled); none yet: no gate.
  SE3 T_ENU_W;
  if (cfg.gps_mode == GpsMode::kJoint && enu_registered) {
    T_ENU_W = SE3(Mat3(Eigen::AngleAxisd(enu_alignment[0], Vec3::UnitZ())),
                  Vec3(enu_alignment[1], enu_alignment[2], enu_alignment[3]));
  } else if (cfg.gps_mode == GpsMode::kDecoupled && decoupled_T_ENU_W) {
    T_ENU_W = *decoupled_T_ENU_W;
  } else {
    return false;
  }
  // The state here is the IMU's prediction (not yet solved): the fix is judged before it can pull.
  Vec3 innovation = fix_enu(fix) - T_ENU_W * (s.T_W_B() * gps_lever_arm_B);
  const WindowState* previous = last_gps_bias_state ? state(*last_gps_bias_state) : nullptr;
  if (previous && cfg.gps_multipath_fraction > 0) {
    const double phi = std::exp(-ns_to_seconds(s.t - previous->t) / cfg.gps_correlation_time_s);
    innovation -= phi * Vec3(previous->gps_bias[0], previous->gps_bias[1], previous->gps_bias[2]);
  }
  const Mat3 S = (1.0 + cfg.gps_multipath_fraction) * fix.covariance_enu;
  const Eigen::LDLT<Mat3> ldlt(S);
  if (ldlt.info() != Eigen::Success || !innovation.allFinite()) return false;
  const double d2 = innovation.dot(ldlt.solve(innovation));
  if (d2 <= cfg.gps_outlier_gate) {
    gps_outlier_since.reset();
    return false;
  }
  if (!gps_outlier_since) gps_outlier_since = s.t;
  return ns_to_seconds(s.t - *gps_outlier_since) <= cfg.gps_max_outlier_s;
}

void SlidingWindowEstimator::Impl::start_gps_bias(WindowState& s) {
  s.has_gps_bias = true;
  s.gps_multipath_covariance = cfg.gps_multipath_fraction * s.gps->covariance_enu;
  const WindowState* previous = last_gps_bias_state ? state(*last_gps_bias_state) : nullptr;
  if (previous) {
    s.gps_bias_previous = previous->id;
    const double phi = std::exp(-ns_to_seconds(s.t - previous->t) / cfg.gps_correlation_time_s);
    for (int i = 0; i < 3; ++i) s.gps_bias[i] = phi * previous->gps_bias[i];  // the process's prediction
  } else {
    s.gps_bias_prior = std::make_shared<MarginalizationPrior>(gaussian_block_prior(
        s.gps_bias, BlockKind::kEuclidean, 3, sqrt_information_of(s.gps_multipath_covariance, "GPS multipath")));
  }
  last_gps_bias_state = s.id;
}

void SlidingWindowEstimator::Impl::register_gps(const WindowState& s) {
  if (enu_registered || !s.gps) return;
  const SE3 T = s.T_W_B();
  registration_pairs.push_back({*s.gps, T * gps_lever_arm_B});
  const GpsRegistration r = registration(registration_pairs);
  if (!r.registered()) return;
  for (int i = 0; i < kEnuAlignmentSize; ++i) enu_alignment[i] = r.alignment(i);
  enu_registered = true;
  // The fixes used here are not factors in the window: their information enters as a Gaussian
  // prior on T_ENU_W (in the marginalization prior's square-root form, J = L^-1, r = 0).
  if (!set_enu_prior(alignment_covariance(r))) return;
  ++stats.gps_registrations;
}

bool SlidingWindowEstimator::Impl::set_enu_prior(const Mat4& covariance) {
  const Eigen::LLT<Mat4> llt(0.5 * (covariance + covariance.transpose()));
  if (llt.info() != Eigen::Success) return false;
  enu_prior = std::make_shared<MarginalizationPrior>(gaussian_block_prior(
      enu_alignment, BlockKind::kEuclidean, kEnuAlignmentSize, llt.matrixL().solve(Mat4::Identity())));
  return true;
}

GpsRegistration SlidingWindowEstimator::Impl::registration(const std::vector<GpsRegistrationPair>& pairs) const {
  GpsRegistrationOptions options;
  options.error_correlation_time_s = cfg.gps_correlation_time_s;  // multipath: not independent fixes
  return register_gps_to_world(pairs, *origin, options);
}

void SlidingWindowEstimator::Impl::reregister_gps(const WindowState& s) {
  if (!s.gps) return;
  registration_pairs.push_back({*s.gps, s.T_W_B() * gps_lever_arm_B});
  const std::size_t keep = static_cast<std::size_t>(cfg.gps_registration_fixes);
  if (keep > 0 && registration_pairs.size() > keep)
    registration_pairs.erase(registration_pairs.begin(),
                             registration_pairs.end() - static_cast<std::ptrdiff_t>(keep));
  const GpsRegistration r = registration(registration_pairs);
  // A failed re-registration (too few or too uncertain fixes) keeps the last good alignment.
  if (!r.registered()) return;
  decoupled_T_ENU_W = r.T_ENU_W();
  decoupled_covariance = alignment_covariance(r);
  ++stats.gps_registrations;
}

void SlidingWindowEstimator::Impl::set_mag_reference(const Vec3& field_B, const SE3& T_W_B) {
  const Vec3 h = T_W_B.q * field_B;
  const Vec3& ref = cfg.mag_reference_field_enu;
  // Rz(psi) turns the field's heading in W into the reference heading in ENU.
  mag_alignment[0] = std::remainder(std::atan2(ref.y(), ref.x()) - std::atan2(h.y(), h.x()), 2.0 * M_PI);
  mag_referenced = true;
  const Mat4 sqrt_info = Eigen::Vector4d(1.0 / kMagHeadingPriorSigma, 1.0 / kMagUnusedPriorSigma,
                                         1.0 / kMagUnusedPriorSigma, 1.0 / kMagUnusedPriorSigma)
                             .asDiagonal();
  mag_prior = std::make_shared<MarginalizationPrior>(
      gaussian_block_prior(mag_alignment, BlockKind::kEuclidean, kEnuAlignmentSize, sqrt_info));
}

bool SlidingWindowEstimator::Impl::magnetically_disturbed(const Vec3& field_B, const WindowState& s) {
  const Vec3& ref = cfg.mag_reference_field_enu;
  const Vec3 h = s.T_W_B().q * field_B;
  constexpr double kDeg = 180.0 / M_PI;
  const auto inclination = [](const Vec3& v) { return std::atan2(v.z(), v.head<2>().norm()); };
  // W and ENU share the up axis: strength and inclination need no heading, only the state's tilt.
  bool off = (cfg.mag_max_norm_deviation > 0 &&
              std::abs(field_B.norm() - ref.norm()) > cfg.mag_max_norm_deviation * ref.norm()) ||
             (cfg.mag_max_inclination_deviation_deg > 0 &&
              std::abs(inclination(h) - inclination(ref)) * kDeg > cfg.mag_max_inclination_deviation_deg);
  if (!off && mag_referenced && cfg.mag_max_heading_deviation_deg > 0) {
    // Rz(psi) turns headings in W into ENU (set_mag_reference).
    const double psi = mag_alignment_block()[0];
    const double heading_off =
        std::remainder(std::atan2(ref.y(), ref.x()) - std::atan2(h.y(), h.x()) - psi, 2.0 * M_PI) * kDeg;
    if (std::abs(heading_off) > cfg.mag_max_heading_deviation_deg) {
      // A heading that disagrees for long is the state's drift, not a disturbance.
      if (!mag_heading_off_since) mag_heading_off_since = s.t;
      off = ns_to_seconds(s.t - *mag_heading_off_since) <= cfg.mag_max_disturbance_s;
      return off;
    }
  }
  mag_heading_off_since.reset();
  return off;
}

void SlidingWindowEstimator::Impl::attach_mag(WindowState& s) {
  if (s.mag_decided) return;
  const Timestamp tolerance = static_cast<Timestamp>(std::llround(cfg.mag_max_time_offset_s * 1e9));
  // Decide once every sample that could be used has arrived (deterministic, whatever the rates).
  if (mag.empty() || mag.back().t <= s.t + tolerance) return;
  s.mag_decided = true;
  const auto after = std::lower_bound(mag.begin(), mag.end(), s.t,
                                      [](const MagSample& m, Timestamp t) { return m.t < t; });
  const MagSample* a = after != mag.begin() && s.t - std::prev(after)->t <= tolerance ? &*std::prev(after) : nullptr;
  const MagSample* b = after != mag.end() && after->t - s.t <= tolerance ? &*after : nullptr;
  Vec3 field;
  if (a && b && b->t > a->t) {
    // The field in B follows the head's rotation: interpolate rather than take the nearest.
    const double u = static_cast<double>(s.t - a->t) / static_cast<double>(b->t - a->t);
    field = (1.0 - u) * a->field + u * b->field;
  } else if (a || b) {
    field = (a && (!b || s.t - a->t <= b->t - s.t)) ? a->field : b->field;
  } else {
    return;
  }
  if (!(field.norm() > 0)) return;
  if (magnetically_disturbed(field, s)) {
    ++stats.mag_disturbed;
    return;
  }
  if (!mag_referenced) set_mag_reference(field, s.T_W_B());  // no sample during the still start
  s.mag_B = field;
}

}  // namespace navaid::estimation
