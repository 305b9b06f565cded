// What the estimator does when a solve is implausible (failure_detection.hpp; docs/estimator.md,
// "Failure detection and recovery"). The window restarts at the failed frame from the newest
// estimate that vision confirmed, carried over the gap at constant velocity with the gyro's
// rotation: the map frame W is kept, and the IMU stretch that caused the failure (a shock, a
// saturation) is not used. Without such an estimate (none yet, too old, or the restarted frame
// fails too) the estimator initializes anew, in a new W.
#include <algorithm>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "impl.hpp"

namespace navaid::estimation {

namespace {

// The inlier shares the collapse test takes its median over [s].
constexpr double kInlierShareHistory = 1.0;
// How far a restart backs off from the newest confirmed estimate [s].
constexpr double kRestartBackoff = 0.2;
// Solves after a restart without the robust loss (fresh tracks, two-view checked by the front end).
constexpr int kRestartGaussianSolves = 3;

}  // namespace

void SlidingWindowEstimator::Impl::clear_window(bool new_map_frame) {
  window.clear();
  gaussian_solves = 0;
  tracks = FeatureTrackStore();
  marginal_prior.reset();
  state_prior.reset();
  last_seen.clear();
  last_gps_bias_state.reset();
  imu_only_since.reset();
  if (!new_map_frame) return;
  ++stats.map_frame_resets;
  initialized = false;
  if (init_method == InitializationMethod::kStill) init_method = InitializationMethod::kHybridPnp;
  enu_registered = false;
  enu_prior.reset();
  registration_pairs.clear();
  decoupled_T_ENU_W.reset();
  mag_referenced = false;
  mag_heading_off_since.reset();
  gps_outlier_since.reset();
  mag_prior.reset();
  last_estimate.reset();
  confirmed.clear();
  inlier_shares.clear();
}

void SlidingWindowEstimator::Impl::record_inlier_share(Timestamp t, VisualSupport& support) {
  while (!inlier_shares.empty() && ns_to_seconds(t - inlier_shares.front().first) > kInlierShareHistory)
    inlier_shares.pop_front();
  std::vector<double> shares;
  for (const auto& [time, share] : inlier_shares) shares.push_back(share);
  if (!shares.empty()) {
    const auto mid = shares.begin() + static_cast<std::ptrdiff_t>(shares.size() / 2);
    std::nth_element(shares.begin(), mid, shares.end());
    support.recent_median = *mid;
  }
  if (support.residuals >= static_cast<std::size_t>(cfg.failure.min_visual_residuals))
    inlier_shares.emplace_back(t, support.inlier_fraction());
}

void SlidingWindowEstimator::Impl::confirm(const StateEstimate& e) {
  confirmed.push_back(e);
  const double keep_s = cfg.restart_max_gap_s + kRestartBackoff;
  while (ns_to_seconds(e.t - confirmed.front().t) > keep_s) confirmed.pop_front();
}

StateEstimate SlidingWindowEstimator::Impl::recover(const FeatureFrame& frame, const std::string& why) {
  ++stats.failures;
  stats.last_failure = why + " at " + std::to_string(ns_to_seconds(frame.t)) + " s";
  // The failed frame's fix goes back to the queue: it is attached again to the frame's new state.
  if (const std::optional<GpsFix> fix = window.back()->gps) pending_fixes.push_front(*fix);
  // Where the frame was placed: its solve may have moved the online time offset since, and the
  // IMU buffered so far covers the placed time, not necessarily frame.t + the new offset.
  const Timestamp t = window.back()->t;
  // The good estimate: the newest confirmed one at least kRestartBackoff older than the newest
  // confirmed (a shock corrupts the velocity at once, the inlier share only as the position error
  // grows: the last frames before the failure may pass with a wrong velocity), else the oldest.
  const StateEstimate* good_ptr = nullptr;
  for (auto it = confirmed.rbegin(); it != confirmed.rend(); ++it) {
    good_ptr = &*it;
    if (ns_to_seconds(confirmed.back().t - it->t) >= kRestartBackoff) break;
  }
  const bool recent = good_ptr && good_ptr->t < frame.t && ns_to_seconds(frame.t - good_ptr->t) <= cfg.restart_max_gap_s;
  const Timestamp t_good = recent ? good_ptr->t + camera_to_imu_ns : 0;
  auto new_map_frame = [&] {
    restarting = false;
    clear_window(/*new_map_frame=*/true);
    return collect_for_visual_initialization(frame, t);
  };
  if (restarting || !recent || imu.empty() || imu.front().t > t_good) return new_map_frame();

  const StateEstimate good = *good_ptr;
  const double dt = ns_to_seconds(frame.t - good.t);
  const ImuPreintegration gyro = ImuPreintegration::between(imu, t_good, t, imu_noise, good.b_g, good.b_a);
  const Mat3 dR = gyro.delta_q().toRotationMatrix();
  const SE3 T(Quat(good.T_W_B.q * gyro.delta_q()).normalized(), good.T_W_B.t + good.v_W * dt);
  // Error propagation of that model: dtheta_k = dR^T dtheta, dp_k = dp + dt dv, the velocity first
  // loosened by restart_sigma_velocity (a failure may have begun before the good estimate), then
  // the walker's unknown acceleration over the gap as white noise of density q: Q_pp = q dt^3/3,
  // Q_pv = q dt^2/2, Q_vv = q dt.
  Mat15 P = 0.5 * (good.covariance + good.covariance.transpose());
  P.block<3, 3>(6, 6) += Mat3::Identity() * cfg.restart_sigma_velocity * cfg.restart_sigma_velocity;
  Mat15 F = Mat15::Identity();
  F.block<3, 3>(0, 0) = dR.transpose();
  F.block<3, 3>(3, 6) = Mat3::Identity() * dt;
  P = F * P * F.transpose();
  const double q = cfg.restart_accel_density * cfg.restart_accel_density;
  P.block<3, 3>(3, 3) += Mat3::Identity() * q * dt * dt * dt / 3.0;
  P.block<3, 3>(3, 6) += Mat3::Identity() * q * dt * dt / 2.0;
  P.block<3, 3>(6, 3) += Mat3::Identity() * q * dt * dt / 2.0;
  P.block<3, 3>(6, 6) += Mat3::Identity() * q * dt;
  P.block<3, 3>(9, 9) += Mat3::Identity() * cfg.init_sigma_gyro_bias * cfg.init_sigma_gyro_bias;
  P.block<3, 3>(12, 12) += Mat3::Identity() * cfg.init_sigma_accel_bias * cfg.init_sigma_accel_bias;
  std::shared_ptr<StatePriorFactor> prior;
  try {
    prior = std::make_shared<StatePriorFactor>(T, good.v_W, good.b_g, good.b_a, Mat15(0.5 * (P + P.transpose())));
  } catch (const Error&) {
    return new_map_frame();
  }
  clear_window(/*new_map_frame=*/false);
  ++stats.restarts;
  auto s = std::make_unique<WindowState>();
  s->id = next_id++;
  s->t = t;
  pose_to_block(T, s->pose);
  for (int i = 0; i < 3; ++i) {
    s->speed_bias[i] = good.v_W[i];
    s->speed_bias[3 + i] = good.b_g[i];
    s->speed_bias[6 + i] = good.b_a[i];
  }
  state_prior = prior;
  state_prior_id = s->id;
  window.push_back(std::move(s));
  WindowState& newest = *window.back();
  add_observations(newest.id, frame);
  if (cfg.use_gps) attach_gps(newest);
  if (cfg.use_mag) attach_mag(newest);

  // Joint GPS: T_ENU_W goes on from the good estimate's value and covariance (the fixes'
  // information in the dropped marginalization prior is kept that way).
  if (enu_registered && good.T_ENU_W && good.T_ENU_W_covariance) {
    enu_alignment[0] = yaw_of(good.T_ENU_W->q);
    for (int i = 0; i < 3; ++i) enu_alignment[1 + i] = good.T_ENU_W->t[i];
    set_enu_prior(*good.T_ENU_W_covariance);
  }
  gaussian_solves = kRestartGaussianSolves + 1;  // the restarted frame's own solve has no visual factor
  restarting = true;
  StateEstimate e = solve_newest(frame, /*keyframe=*/true);
  restarting = false;
  return e;
}

}  // namespace navaid::estimation
