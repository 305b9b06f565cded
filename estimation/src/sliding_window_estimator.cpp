#include "navaid/estimation/sliding_window_estimator.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/estimation/failure_detection.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/gauss_markov_factor.hpp"
#include "navaid/estimation/factors/gps_position_factor.hpp"
#include "navaid/estimation/factors/imu_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/landmark_factors.hpp"
#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/factors/time_offset_factors.hpp"
#include "navaid/estimation/factors/zero_velocity_factor.hpp"
#include "navaid/estimation/feature_track_store.hpp"
#include "navaid/estimation/gps_registration.hpp"
#include "navaid/estimation/imu_preintegration.hpp"
#include "navaid/estimation/marginalization.hpp"
#include "navaid/estimation/state_prior_factor.hpp"
#include "navaid/estimation/first_estimates.hpp"
#include "sliding_window/impl.hpp"
#include "sliding_window/inlier_gate.hpp"

namespace navaid::estimation {

namespace {

std::shared_ptr<ceres::LossFunction> make_loss(const EstimatorConfig& cfg) {
  switch (cfg.loss) {
    case LossKind::kCauchy: return std::make_shared<ceres::CauchyLoss>(cfg.loss_scale);
    case LossKind::kHuber: return std::make_shared<ceres::HuberLoss>(cfg.loss_scale);
    case LossKind::kNone: return nullptr;
  }
  return nullptr;
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

ceres::LinearSolverType solver_type(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kDenseSchur: return ceres::DENSE_SCHUR;
    case LinearSolverKind::kSparseSchur: return ceres::SPARSE_SCHUR;
    case LinearSolverKind::kSparseNormalCholesky: return ceres::SPARSE_NORMAL_CHOLESKY;
  }
  return ceres::DENSE_SCHUR;
}

}  // namespace

SlidingWindowEstimator::Impl::Impl(const RigCalibration& rig, const EstimatorConfig& config,
                                   const std::string& camera_name, const std::optional<GeodeticOrigin>& geodetic_origin)
    : cfg(config), origin(geodetic_origin), gps_lever_arm_B(rig.gps_lever_arm_B), init_method(config.init_method) {
  if (cfg.use_gps && !origin)
    throw ConfigError("recording", "origin", "GPS factors need the geodetic origin of the ENU frame");
  gps_loss = std::make_shared<ceres::HuberLoss>(cfg.gps_huber_threshold);
  if (rig.cameras.empty()) throw ConfigError("calibration", "cameras", "the estimator needs a camera");
  const CameraCalibration* cam = &rig.cameras.front();
  if (!camera_name.empty()) {
    cam = nullptr;
    for (const auto& c : rig.cameras)
      if (c.name == camera_name) cam = &c;
    if (!cam) throw ConfigError("calibration", "cameras", "no camera named '" + camera_name + "'");
  }
  camera = *cam;
  camera_model = make_camera_model(camera, "calibration");
  if (!rig.imu) throw ConfigError("calibration", "imu", "the estimator needs an IMU calibration");
  imu_noise = ImuNoise::from(*rig.imu);
  // A real IMU on a vibrating platform is noisier than its datasheet (docs/estimator.md).
  imu_noise.gyro_noise_density *= cfg.imu_noise_scale;
  imu_noise.accel_noise_density *= cfg.imu_noise_scale;
  imu_noise.gyro_random_walk *= cfg.imu_random_walk_scale;
  imu_noise.accel_random_walk *= cfg.imu_random_walk_scale;
  imu_noise.max_sample_gap_s = cfg.imu_max_sample_gap_s;
  imu_noise.gap_gyro_density = cfg.imu_gap_gyro_density;
  imu_noise.gap_accel_density = cfg.imu_gap_accel_density;
  validate(imu_noise, "calibration: imu");
  focal_px = std::sqrt(camera.fx * camera.fy);
  camera_to_imu_ns = static_cast<Timestamp>(std::llround(camera.time_offset_s * 1e9));
  time_offset[0] = camera.time_offset_s;
  if (cfg.estimate_time_offset)
    time_offset_prior = std::make_shared<MarginalizationPrior>(gaussian_block_prior(
        time_offset, BlockKind::kEuclidean, 1, Eigen::MatrixXd::Constant(1, 1, 1.0 / cfg.time_offset_sigma_s)));
  pose_to_block(camera.T_B_C, extrinsic);
  if (cfg.estimate_extrinsic) {
    // Pose tangent [dp, d] with rotation vector 2 d (pose_parametrization.hpp).
    Eigen::Matrix<double, 6, 1> inv_sigma;
    inv_sigma << Vec3::Constant(1.0 / cfg.extrinsic_sigma_translation_m),
        Vec3::Constant(2.0 / cfg.extrinsic_sigma_rotation_rad);
    extrinsic_prior = std::make_shared<MarginalizationPrior>(
        gaussian_block_prior(extrinsic, BlockKind::kPose, kPoseSize, Eigen::MatrixXd(inv_sigma.asDiagonal())));
  }

  const double sigma_d = cfg.disparity_sigma_px > 0 ? cfg.disparity_sigma_px : camera.depth_disparity_sigma_px;
  const double baseline = cfg.depth_baseline_m > 0 ? cfg.depth_baseline_m : camera.depth_baseline_m;
  if (sigma_d > 0 && baseline > 0) sigma_lambda = inverse_depth_sigma(sigma_d, focal_px, baseline);
  if (cfg.use_depth && (cfg.use_inverse_depth || cfg.use_depth_3d) && sigma_lambda <= 0)
    throw ConfigError("calibration", "cameras." + camera.name + ".depth",
                      "depth factors need the depth baseline and disparity sigma (calibration or "
                      "estimator.depth.baseline / estimator.depth.disparity_sigma), or estimator.depth.enabled=false");
  robust_loss = make_loss(cfg);
  if (robust_loss) loss = std::make_shared<ceres::LossFunctionWrapper>(robust_loss.get(), ceres::DO_NOT_TAKE_OWNERSHIP);
  if (cfg.use_mag) mag_sigma_yaw = magnetometer_yaw_sigma(cfg.mag_sigma, cfg.mag_reference_field_enu);
}

SlidingWindowEstimator::Impl::Impl(const Impl& o)
    : cfg(o.cfg),
      camera(o.camera),
      camera_model(o.camera_model),
      imu_noise(o.imu_noise),
      focal_px(o.focal_px),
      sigma_lambda(o.sigma_lambda),
      camera_to_imu_ns(o.camera_to_imu_ns),
      extrinsic_prior(o.extrinsic_prior ? std::make_shared<MarginalizationPrior>(*o.extrinsic_prior) : nullptr),
      time_offset_prior(o.time_offset_prior ? std::make_shared<MarginalizationPrior>(*o.time_offset_prior) : nullptr),
      last_seen(o.last_seen),
      loss(o.loss),
      robust_loss(o.robust_loss),
      origin(o.origin),
      gps_lever_arm_B(o.gps_lever_arm_B),
      gps_loss(o.gps_loss),
      pending_fixes(o.pending_fixes),
      registration_pairs(o.registration_pairs),
      enu_registered(o.enu_registered),
      enu_prior(o.enu_prior ? std::make_shared<MarginalizationPrior>(*o.enu_prior) : nullptr),
      last_gps_bias_state(o.last_gps_bias_state),
      decoupled_T_ENU_W(o.decoupled_T_ENU_W),
      decoupled_covariance(o.decoupled_covariance),
      mag(o.mag),
      mag_sigma_yaw(o.mag_sigma_yaw),
      mag_referenced(o.mag_referenced),
      mag_heading_off_since(o.mag_heading_off_since),
      gps_outlier_since(o.gps_outlier_since),
      mag_prior(o.mag_prior ? std::make_shared<MarginalizationPrior>(*o.mag_prior) : nullptr),
      tracks(o.tracks),
      imu(o.imu),
      pending(o.pending),
      recent_frames(o.recent_frames),
      state_prior(o.state_prior),
      state_prior_id(o.state_prior_id),
      next_id(o.next_id),
      initialized(o.initialized),
      init_method(o.init_method),
      restarting(o.restarting),
      gaussian_solves(o.gaussian_solves),
      confirmed(o.confirmed),
      inlier_shares(o.inlier_shares),
      last_event_t(o.last_event_t),
      imu_only_since(o.imu_only_since),
      last_estimate(o.last_estimate),
      stats(o.stats) {
  std::copy(o.extrinsic, o.extrinsic + kPoseSize, extrinsic);
  std::copy(o.enu_alignment, o.enu_alignment + kEnuAlignmentSize, enu_alignment);
  std::copy(o.mag_alignment, o.mag_alignment + kEnuAlignmentSize, mag_alignment);
  std::unordered_map<const double*, double*> moved;
  moved[o.enu_alignment] = enu_alignment;
  moved[o.mag_alignment] = mag_alignment;
  moved[o.extrinsic] = extrinsic;
  time_offset[0] = o.time_offset[0];
  moved[o.time_offset] = time_offset;
  for (const auto& s : o.window) {
    window.push_back(std::make_unique<WindowState>(*s));
    moved[s->pose] = window.back()->pose;
    moved[s->speed_bias] = window.back()->speed_bias;
    moved[s->gps_bias] = window.back()->gps_bias;
  }
  for (auto& s : window)
    if (s->gps_bias_prior) {
      s->gps_bias_prior = std::make_shared<MarginalizationPrior>(*s->gps_bias_prior);
      s->gps_bias_prior->remap(moved);
    }
  if (enu_prior) enu_prior->remap(moved);
  if (mag_prior) mag_prior->remap(moved);
  if (extrinsic_prior) extrinsic_prior->remap(moved);
  if (time_offset_prior) time_offset_prior->remap(moved);
  for (auto& [id, track] : tracks.tracks()) {
    const FeatureTrack& from = o.tracks.tracks().at(id);
    moved[from.landmark] = track.landmark;
    moved[&from.landmark[2]] = &track.landmark[2];
  }
  if (o.marginal_prior) {
    marginal_prior = std::make_shared<MarginalizationPrior>(*o.marginal_prior);
    marginal_prior->remap(moved);
  }
}

const WindowState* SlidingWindowEstimator::Impl::state(std::uint64_t id) const {
  for (const auto& s : window)
    if (s->id == id) return s.get();
  return nullptr;
}

std::vector<StateEstimate> SlidingWindowEstimator::Impl::process(const SensorEvent& event) {
  const Timestamp t = event_time(event);
  if (t < last_event_t)
    throw Error("estimator: events out of time order (" + std::to_string(t) + " ns after " +
                std::to_string(last_event_t) + " ns)");
  last_event_t = t;
  std::vector<StateEstimate> out;
  stage_times.clear();
  if (const auto* s = std::get_if<ImuSample>(&event)) {
    if (!s->has_gyro) throw Error("estimator: IMU sample without gyro data at " + std::to_string(s->t) + " ns");
    if (!imu.empty() && s->t <= imu.back().t) return out;  // duplicate time stamp: keep the first
    imu.push_back(*s);
    trim_imu();
  } else if (const auto* f = std::get_if<FeatureFrame>(&event)) {
    if (f->camera == camera.name) pending.push_back(*f);
  } else if (std::holds_alternative<RgbdFrame>(event)) {
    throw Error("image front end not available yet: run on a feature-level recording");
  }
  if (const auto* g = std::get_if<GpsFix>(&event)) {
    if (cfg.use_gps && g->mode != GpsFixMode::kNoFix && ellipsoidal_height_m(*g)) pending_fixes.push_back(*g);
  }
  if (const auto* m = std::get_if<MagSample>(&event)) {
    if (cfg.use_mag && m->field.allFinite() && (mag.empty() || m->t > mag.back().t))
      mag.push_back({m->t, calibrated_mag_field(cfg, m->field)});
  }
  while (!pending.empty() && !imu.empty() && pending.front().t + camera_to_imu_ns <= imu.back().t) {
    frame_stages = {};
    out.push_back(handle_frame(pending.front()));
    stage_times.push_back(frame_stages);
    pending.pop_front();
  }
  return out;
}

void SlidingWindowEstimator::Impl::trim_imu() {
  if (window.empty() || imu.size() < 4096) return;
  const Timestamp keep_from = window.front()->t;
  std::size_t first = 0;
  while (first + 1 < imu.size() && imu[first + 1].t <= keep_from) ++first;
  if (first > 2048) imu.erase(imu.begin(), imu.begin() + static_cast<std::ptrdiff_t>(first));
}

Mat15 SlidingWindowEstimator::Impl::initial_covariance(const Quat& q, double extra_sigma_roll_pitch) const {
  Mat15 P = Mat15::Zero();
  // Roll and pitch come from gravity; yaw and position define W (world-frame angles, converted
  // to the right perturbation of StateEstimate).
  const double sigma_rp = std::hypot(cfg.init_sigma_roll_pitch_rad, extra_sigma_roll_pitch);
  const Vec3 sigma_world(sigma_rp, sigma_rp, kGaugeSigma);
  const Mat3 R = q.toRotationMatrix();
  P.block<3, 3>(0, 0) = R.transpose() * sigma_world.cwiseAbs2().asDiagonal() * R;
  P.block<3, 3>(3, 3) = Mat3::Identity() * kGaugeSigma * kGaugeSigma;
  P.block<3, 3>(6, 6) = Mat3::Identity() * cfg.init_sigma_velocity * cfg.init_sigma_velocity;
  P.block<3, 3>(9, 9) = Mat3::Identity() * cfg.init_sigma_gyro_bias * cfg.init_sigma_gyro_bias;
  P.block<3, 3>(12, 12) = Mat3::Identity() * cfg.init_sigma_accel_bias * cfg.init_sigma_accel_bias;
  return P;
}

StateEstimate SlidingWindowEstimator::Impl::estimate_of(const WindowState& s, Timestamp frame_t, EstimatorMode mode,
                                                        const Mat15& cov) const {
  StateEstimate e;
  e.t = frame_t;
  e.T_W_B = s.T_W_B();
  e.v_W = s.v();
  e.b_g = s.b_g();
  e.b_a = s.b_a();
  e.covariance = cov;
  e.mode = mode;
  return e;
}

void SlidingWindowEstimator::Impl::add_observations(std::uint64_t frame_id, const FeatureFrame& frame) {
  std::vector<std::pair<std::uint64_t, TrackObservation>> obs;
  obs.reserve(frame.features.size());
  std::unordered_map<std::uint64_t, LastSeen> seen;
  for (const auto& f : frame.features) {
    const auto m = camera_model->undistort(camera_model->distorted_from_pixel(f.uv));
    if (!m) continue;
    TrackObservation o;
    o.m = *m;
    o.uv = f.uv;
    if (cfg.use_depth && f.depth_m && std::isfinite(*f.depth_m) && *f.depth_m > 0) o.depth_m = f.depth_m;
    o.td0_s = ns_to_seconds(camera_to_imu_ns);
    // Backward difference over the previous frame that saw the track (frames keep their camera
    // stamps here: only differences enter).
    const auto last = last_seen.find(f.track_id);
    if (last != last_seen.end() && frame.t > last->second.t) {
      const double dt = ns_to_seconds(frame.t - last->second.t);
      o.velocity = (o.m - last->second.m) / dt;
      if (o.depth_m && last->second.depth_m) o.depth_rate_mps = (*o.depth_m - *last->second.depth_m) / dt;
    }
    seen[f.track_id] = {frame.t, o.m, o.depth_m};
    obs.emplace_back(f.track_id, o);
  }
  last_seen = std::move(seen);
  tracks.add_frame(frame_id, obs);
}

bool SlidingWindowEstimator::Impl::decide_keyframe(const WindowState& last_keyframe, const WindowState& newest,
                                                   std::size_t observed) const {
  int common = 0;
  const double parallax = tracks.mean_parallax_px(last_keyframe.id, newest.id, &common);
  if (common > 0 && parallax >= cfg.keyframe_parallax_px) return true;
  // Track loss: few tracks shared with the last keyframe while new ones appeared (they need an
  // anchor in the window). A frame that sees next to nothing gains nothing from being a keyframe.
  if (common < cfg.keyframe_min_tracked && observed > static_cast<std::size_t>(common)) return true;
  return ns_to_seconds(newest.t - last_keyframe.t) >= cfg.keyframe_max_interval_s;
}

std::optional<double> SlidingWindowEstimator::Impl::triangulate(const FeatureTrack& track) const {
  const WindowState* anchor = state(track.anchor().frame_id);
  if (!anchor) return std::nullopt;
  const SE3 T_W_Ca = T_W_C(*anchor);
  // Linear triangulation in the anchor camera: m_j x (R_ja P + t_ja) = 0 for every observation.
  Mat3 A = Mat3::Zero();
  Vec3 b = Vec3::Zero();
  double max_angle = 0;
  const Vec3 ray_a = T_W_Ca.q * Vec3(track.anchor().m.x(), track.anchor().m.y(), 1.0).normalized();
  for (const auto& o : track.observations) {
    const WindowState* s = state(o.frame_id);
    if (!s) return std::nullopt;
    const SE3 T_j_a = T_W_C(*s).inverse() * T_W_Ca;
    const Vec3 m(o.m.x(), o.m.y(), 1.0);
    const Mat3 M = hat(m);
    const Eigen::Matrix3d MR = M * T_j_a.rotation();
    A += MR.transpose() * MR;
    b -= MR.transpose() * (M * T_j_a.t);
    const Vec3 ray = T_W_C(*s).q * m.normalized();
    max_angle = std::max(max_angle, std::acos(std::clamp(ray.dot(ray_a), -1.0, 1.0)));
  }
  if (max_angle < kMinTriangulationAngle) return std::nullopt;
  const Eigen::LDLT<Mat3> ldlt(A);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  const Vec3 P = ldlt.solve(b);
  if (!P.allFinite() || P.z() < kMinFeatureDepth || P.z() > kMaxFeatureDepth) return std::nullopt;
  return 1.0 / P.z();
}

void SlidingWindowEstimator::Impl::initialize_tracks() {
  for (auto& [id, track] : tracks.tracks()) {
    if (track.initialized) continue;
    track.landmark[0] = track.anchor().m.x();
    track.landmark[1] = track.anchor().m.y();
    if (track.anchor().depth_m) {
      track.inverse_depth() = 1.0 / *track.anchor().depth_m;
      track.initialized = true;
    } else if (track.observations.size() >= 2) {
      if (const auto lambda = triangulate(track)) {
        track.inverse_depth() = *lambda;
        track.initialized = true;
      }
    }
  }
}

std::vector<Residual> SlidingWindowEstimator::Impl::build_residuals(VisualCount* count,
                                                                    std::vector<double*>* constant_blocks) {
  std::vector<Residual> out;
  // IMU between consecutive states, re-integrated when the bias moved far from its linearization.
  for (std::size_t i = 1; i < window.size() && cfg.use_imu; ++i) {
    WindowState& prev = *window[i - 1];
    WindowState& cur = *window[i];
    cur.imu->repropagate_if_needed(prev.b_g(), prev.b_a(), kRepropagateGyro, kRepropagateAccel);
    out.push_back({std::make_shared<ImuFactor>(*cur.imu), nullptr, {prev.pose, prev.speed_bias, cur.pose, cur.speed_bias}});
  }
  for (auto& s : window)
    if (s->still && cfg.use_imu)
      out.push_back({std::make_shared<ZeroVelocityFactor>(cfg.zero_velocity_sigma_mps, s->still->mean, s->still->sigma),
                     nullptr, {s->speed_bias}});
  if (marginal_prior && !marginal_prior->empty())
    out.push_back({std::make_shared<MarginalizationFactor>(marginal_prior), nullptr, marginal_prior->blocks});
  if (state_prior) {
    for (auto& s : window)
      if (s->id == state_prior_id) out.push_back({state_prior, nullptr, {s->pose, s->speed_bias}});
  }

  if (enu_prior) out.push_back({std::make_shared<MarginalizationFactor>(enu_prior), nullptr, enu_prior->blocks});
  if (mag_prior) out.push_back({std::make_shared<MarginalizationFactor>(mag_prior), nullptr, mag_prior->blocks});
  if (extrinsic_prior)
    out.push_back({std::make_shared<MarginalizationFactor>(extrinsic_prior), nullptr, extrinsic_prior->blocks});
  if (time_offset_prior)
    out.push_back({std::make_shared<MarginalizationFactor>(time_offset_prior), nullptr, time_offset_prior->blocks});
  if (enu_registered) {
    for (auto& s : window) {
      if (!s->gps) continue;
      if (!s->has_gps_bias) {
        out.push_back({std::make_shared<GpsPositionFactor>(fix_enu(*s->gps), s->gps->covariance_enu, gps_lever_arm_B),
                       gps_loss, {s->pose, enu_alignment}});
        continue;
      }
      const Mat3 white = s->gps->covariance_enu - s->gps_multipath_covariance;
      out.push_back({std::make_shared<GpsPositionBiasFactor>(fix_enu(*s->gps), white, gps_lever_arm_B), gps_loss,
                     {s->pose, enu_alignment, s->gps_bias}});
      if (s->gps_bias_prior) {
        out.push_back({std::make_shared<MarginalizationFactor>(s->gps_bias_prior), nullptr, s->gps_bias_prior->blocks});
      } else if (s->gps_bias_previous) {
        // A predecessor that left the window passed its link on in the marginalization prior.
        for (auto& p : window)
          if (p->id == *s->gps_bias_previous)
            out.push_back({std::make_shared<GaussMarkovFactor>(ns_to_seconds(s->t - p->t), cfg.gps_correlation_time_s,
                                                               s->gps_multipath_covariance),
                           nullptr, {p->gps_bias, s->gps_bias}});
      }
    }
  }

  for (auto& s : window) {
    // A field without a horizontal part at the current attitude has no heading (the factor could
    // not be evaluated): leave it out of this solve.
    if (!s->mag_B) continue;
    const Vec3 h = s->T_W_B().q * *s->mag_B;
    if (h.head<2>().norm() < 1e-3 * h.norm()) continue;
    out.push_back({std::make_shared<MagnetometerYawFactor>(*s->mag_B, cfg.mag_reference_field_enu, mag_sigma_yaw),
                   nullptr, {s->pose, mag_alignment_block()}});
  }

  const std::uint64_t newest_id = window.back()->id;
  VisualCount c;
  for (auto& [id, track] : tracks.tracks()) {
    // A handed-over track's anchor is its frozen pose and every observation is a target.
    const bool handed_over = track.handed_over;
    if (!track.initialized || track.observations.size() < (handed_over ? 1u : 2u)) continue;
    const TrackObservation& a = track.anchor();
    double* anchor_pose = handed_over ? track.frozen_anchor_pose : nullptr;
    for (auto& s : window)
      if (!handed_over && s->id == a.frame_id) anchor_pose = s->pose;
    if (!anchor_pose) continue;
    if (handed_over && constant_blocks) constant_blocks->push_back(anchor_pose);
    const SE3 T_W_Ca = pose_from_block(anchor_pose) * pose_from_block(extrinsic);
    // near: the anchor's depth measurement is used (anchor factors, and the targets' depths).
    const bool near = !handed_over && a.depth_m && *a.depth_m <= cfg.far_threshold_m && sigma_lambda > 0;
    const bool target_depths = near || (handed_over && sigma_lambda > 0);
    const bool fixed = far_fixed(track);
    // A landmark held constant keeps its bearing too (the plain factors, VINS-RGBD style).
    const bool estimated = handed_over || (bearing_estimated() && !fixed);
    double* landmark = landmark_block(track);
    std::vector<Residual> r;
    bool depth_factor = false;
    bool sees_newest = false;
    for (std::size_t k = handed_over ? 0 : 1; k < track.observations.size(); ++k) {
      const TrackObservation& o = track.observations[k];
      WindowState* target = nullptr;
      for (auto& s : window)
        if (s->id == o.frame_id) target = s.get();
      if (!target) continue;
      // A point behind the target camera at the current estimate cannot be evaluated (the factor
      // returns false and Ceres aborts): leave that observation out of this solve.
      const Eigen::Vector2d m_a = track.bearing();
      const Vec3 p_ct = T_W_C(*target).inverse() * (T_W_Ca * (Vec3(m_a.x(), m_a.y(), 1.0) / track.inverse_depth()));
      if (!(p_ct.z() > kMinFeatureDepth)) continue;
      sees_newest |= o.frame_id == newest_id;
      std::vector<double*> blocks{anchor_pose, target->pose, extrinsic, landmark};
      const TimedObservation ta{a.m, a.velocity, a.td0_s}, to{o.m, o.velocity, o.td0_s};
      if (cfg.estimate_time_offset) blocks.push_back(time_offset);
      const bool td = cfg.estimate_time_offset;
      if (estimated) {
        if (target_depths && cfg.use_depth_3d && o.depth_m && *o.depth_m <= cfg.far_threshold_m) {
          const double sl = sigma_lambda, sp = cfg.pixel_sigma_px;
          const auto model = cfg.depth_3d_covariance;
          r.push_back({td ? std::shared_ptr<ceres::CostFunction>(std::make_shared<LandmarkDepth3dTdFactor>(
                                to, *o.depth_m, o.depth_rate_mps, focal_px, sl, sp, model))
                          : std::make_shared<LandmarkDepth3dFactor>(o.m, *o.depth_m, focal_px, sl, sp, model),
                       loss, blocks});
          depth_factor = true;
        } else if (cfg.use_reprojection) {
          r.push_back({td ? std::shared_ptr<ceres::CostFunction>(
                                std::make_shared<LandmarkReprojectionTdFactor>(to, focal_px, cfg.pixel_sigma_px))
                          : std::make_shared<LandmarkReprojectionFactor>(o.m, focal_px, cfg.pixel_sigma_px),
                       loss, blocks});
        }
        continue;
      }
      if (near && cfg.use_depth_3d && o.depth_m && *o.depth_m <= cfg.far_threshold_m) {
        if (cfg.estimate_time_offset)
          r.push_back({std::make_shared<Depth3dTdFactor>(ta, to, *o.depth_m, o.depth_rate_mps, focal_px, sigma_lambda,
                                                         cfg.pixel_sigma_px, cfg.depth_3d_covariance),
                       loss, blocks});
        else
          r.push_back({std::make_shared<Depth3dFactor>(m_a, o.m, *o.depth_m, focal_px, sigma_lambda, cfg.pixel_sigma_px,
                                                       cfg.depth_3d_covariance),
                       loss, blocks});
        depth_factor = true;
      } else if (cfg.use_reprojection) {
        if (cfg.estimate_time_offset)
          r.push_back({std::make_shared<ReprojectionTdFactor>(ta, to, focal_px, cfg.pixel_sigma_px), loss, blocks});
        else
          r.push_back({std::make_shared<ReprojectionFactor>(m_a, o.m, focal_px, cfg.pixel_sigma_px), loss, blocks});
      }
    }
    if (r.empty()) continue;
    if (handed_over) {
      // The anchor observation went into the prior with the anchor keyframe.
    } else if (estimated && cfg.estimate_time_offset) {
      const TimedObservation ta{a.m, a.velocity, a.td0_s};
      r.push_back({std::make_shared<AnchorBearingTdFactor>(ta, focal_px, cfg.pixel_sigma_px), loss,
                   {track.landmark, time_offset}});
    } else if (estimated) {
      r.push_back({std::make_shared<AnchorBearingFactor>(a.m, focal_px, cfg.pixel_sigma_px), loss, {track.landmark}});
    }
    // A free far feature's weak depth prior (EstimatorConfig::far_depth_sigma_scale): not a depth
    // factor of the paper's, only what keeps its inverse depth determined while the camera turns.
    const bool far_prior = !handed_over && !near && !fixed && a.depth_m && sigma_lambda > 0 && cfg.far_depth_sigma_scale > 0;
    const double far_sigma = sigma_lambda * cfg.far_depth_sigma_scale;
    if (estimated) {
      if (near && cfg.use_inverse_depth) {
        r.push_back({std::make_shared<AnchorInverseDepthFactor>(*a.depth_m, sigma_lambda), nullptr, {track.landmark}});
        depth_factor = true;
      } else if (far_prior) {
        r.push_back({std::make_shared<AnchorInverseDepthFactor>(*a.depth_m, far_sigma), nullptr, {track.landmark},
                     "far_depth_prior"});
      }
    } else if (near && cfg.use_inverse_depth) {
      r.push_back({std::make_shared<InverseDepthFactor>(*a.depth_m, sigma_lambda), nullptr, {&track.inverse_depth()}});
      depth_factor = true;
    } else if (far_prior) {
      r.push_back({std::make_shared<InverseDepthFactor>(*a.depth_m, far_sigma), nullptr, {&track.inverse_depth()},
                   "far_depth_prior"});
    }
    if (fixed && constant_blocks) constant_blocks->push_back(&track.inverse_depth());
    ++c.all_features;
    if (sees_newest || a.frame_id == newest_id) {
      ++c.features;
      if (depth_factor) ++c.depth_features;
    }
    for (auto& x : r) out.push_back(std::move(x));
  }
  if (count) *count = c;
  if (cfg.first_estimates && marginal_prior && !marginal_prior->empty())
    for (Residual& r : out)
      if (!dynamic_cast<const MarginalizationFactor*>(r.cost.get()) &&
          FirstEstimateCost::touches(r.blocks, *marginal_prior))
        r.cost = std::make_shared<FirstEstimateCost>(r.cost, r.blocks, marginal_prior, pose_manifold);
  return out;
}

std::shared_ptr<ceres::ParameterBlockOrdering> SlidingWindowEstimator::Impl::schur_ordering(
    const ceres::Problem& problem, const std::vector<Residual>& residuals) {
  if (cfg.schur_ordering == SchurOrdering::kCeres || cfg.linear_solver == LinearSolverKind::kSparseNormalCholesky)
    return nullptr;
  std::unordered_set<const double*> landmarks;
  for (auto& [id, track] : tracks.tracks()) {
    // A landmark the prior holds shares the prior's residual with others: not an independent set.
    const double* landmark = landmark_block(track);
    if (problem.HasParameterBlock(landmark) && !problem.IsParameterBlockConstant(landmark) &&
        !in_marginal_prior(landmark))
      landmarks.insert(landmark);
  }
  // Nothing to eliminate (no landmark in this solve): Ceres chooses.
  if (landmarks.empty()) return nullptr;
  if (cfg.schur_ordering == SchurOrdering::kAuto) {
    // Fixed-size kernels need every landmark row block of one size with pose blocks only (VIO's
    // 2-row reprojection and anchor bearing). Otherwise (depth factors of 3 and 1 rows, td)
    // Ceres' independent set, which also eliminates speed-bias blocks, leaves a smaller reduced
    // system for its dynamic kernels and was faster (docs/estimator.md, "Schur ordering").
    for (const Residual& r : residuals) {
      bool on_landmark = false, on_other = false;
      for (const double* b : r.blocks) {
        if (landmarks.count(b)) on_landmark = true;
        else if (!problem.IsParameterBlockConstant(b) && problem.ParameterBlockTangentSize(b) != kPoseTangentSize)
          on_other = true;
      }
      if (on_landmark && (r.cost->num_residuals() != 2 || on_other)) return nullptr;
    }
  }
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  for (double* b : blocks) ordering->AddElementToGroup(b, landmarks.count(b) ? 0 : 1);
  return ordering;
}

VisualCount SlidingWindowEstimator::Impl::solve(std::optional<NewestCovariance>* covariance, bool newest_only) {
  ceres::Problem::Options po;
  // The problem borrows the factors, losses and manifold; they live in this scope.
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  VisualCount count;
  std::vector<double*> fixed;
  const std::vector<Residual> residuals = build_residuals(&count, &fixed);
  for (auto& s : window) {
    problem.AddParameterBlock(s->pose, kPoseSize, pose_manifold.get());
    problem.AddParameterBlock(s->speed_bias, kSpeedBiasSize);
    if (!cfg.use_imu) problem.SetParameterBlockConstant(s->speed_bias);
  }
  problem.AddParameterBlock(extrinsic, kPoseSize, pose_manifold.get());
  if (!cfg.estimate_extrinsic) problem.SetParameterBlockConstant(extrinsic);
  for (const auto& r : residuals) problem.AddResidualBlock(r.cost.get(), r.loss.get(), r.blocks);
  for (double* lambda : fixed) problem.SetParameterBlockConstant(lambda);
  if (!cfg.use_imu && !state_prior && (!marginal_prior || marginal_prior->empty()))
    problem.SetParameterBlockConstant(window.front()->pose);  // without IMU nothing else holds the gauge

  // Motion-only: every other block held where the last solve left it, released again for the
  // covariance (which is the whole window's).
  std::vector<double*> held;
  if (newest_only) {
    std::vector<double*> blocks;
    problem.GetParameterBlocks(&blocks);
    for (double* b : blocks)
      if (b != window.back()->pose && b != window.back()->speed_bias && !problem.IsParameterBlockConstant(b)) {
        problem.SetParameterBlockConstant(b);
        held.push_back(b);
      }
  }

  ceres::Solver::Options so;
  so.linear_solver_type = newest_only ? ceres::DENSE_QR : solver_type(cfg.linear_solver);
  so.max_num_iterations = cfg.max_iterations;
  if (!newest_only) so.linear_solver_ordering = schur_ordering(problem, residuals);
  if (cfg.max_solver_time_s > 0) so.max_solver_time_in_seconds = cfg.max_solver_time_s;
  so.num_threads = 1;
  // Converged when an iteration gains less than 1e-4 of the cost (Ceres' default 1e-6 kept three
  // quarters of the solves at max_iterations for sub-millimetre changes): measured -11 to -28 %
  // estimator time, ATE within +-3 mm on lab walks (docs/estimator.md, "navaid run").
  so.function_tolerance = 1e-4;
  // A motion-only solve is small and cheap: to convergence (1e-4 left it at the IMU prediction
  // in half the frames, the first step's gain on the frame's own residuals being below that).
  if (newest_only) so.function_tolerance = 1e-8;
  if (gaussian_solves > 0) {
    // A restarted window: few states, a velocity far from its estimate (Levenberg-Marquardt moves
    // it a fraction of the way per iteration): run to convergence.
    so.max_num_iterations = std::max(cfg.max_iterations, kRestartMaxIterations);
    so.function_tolerance = 1e-8;
  }
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  {
    const sliding_window::GatedLoss plain(loss.get(), robust_loss.get(), gaussian_solves > 0, /*gaussian=*/true);
    ceres::Solve(so, &problem, &summary);
  }
  for (double* b : held) problem.SetParameterBlockVariable(b);
  if (gaussian_solves > 0) --gaussian_solves;
  ++stats.solves;
  stats.solver_iterations += summary.iterations.size() > 0 ? summary.iterations.size() - 1 : 0;
  if (summary.termination_type == ceres::NO_CONVERGENCE) ++stats.solves_at_iteration_cap;
  count.solver_failed = summary.termination_type == ceres::FAILURE;
  if (cfg.failure_detection) count_newest_inliers(residuals, count);
  if (cfg.residual_diagnostics) accumulate_residual_statistics(residuals);
  stats.features_in_last_solve = count.all_features;
  stats.depth_features_in_last_solve = count.depth_features;
  // New frames are placed in the IMU clock with the current offset estimate.
  if (cfg.estimate_time_offset) camera_to_imu_ns = static_cast<Timestamp>(std::llround(time_offset[0] * 1e9));
  if (covariance) {
    const auto start = std::chrono::steady_clock::now();
    *covariance = newest_covariance(problem, residuals);
    frame_stages.covariance_ms += ms_since(start);
  }
  return count;
}

void SlidingWindowEstimator::Impl::remove_failed_tracks() {
  std::vector<std::uint64_t> failed;
  for (const auto& [id, track] : tracks.tracks()) {
    if (!track.initialized) continue;
    const double z = 1.0 / track.inverse_depth();
    if (!std::isfinite(z) || z < kMinFeatureDepth || z > kMaxFeatureDepth) failed.push_back(id);
  }
  drop_from_marginal_prior(failed);
  for (auto id : failed) tracks.erase(id);
}

std::set<const double*> SlidingWindowEstimator::Impl::hand_over_tracks_of(const WindowState& leaving) {
  std::set<const double*> kept;
  const std::uint64_t newest_id = window.back()->id;
  for (auto id : tracks.anchored_at(leaving.id)) {
    FeatureTrack& track = tracks.tracks().at(id);
    const bool alive = track.observations.back().frame_id == newest_id && track.observations.size() >= 2;
    if (!alive || !track.initialized || landmark_block(track) != track.landmark) continue;
    if (!track.handed_over) {
      // The landmark's numbers stay as they are: anchored at this pose, now frozen.
      std::copy(leaving.pose, leaving.pose + kPoseSize, track.frozen_anchor_pose);
      track.handed_over = true;
      ++stats.handed_over_tracks;
    }
    kept.insert(track.landmark);
  }
  return kept;
}

void SlidingWindowEstimator::Impl::drop_from_marginal_prior(const std::vector<std::uint64_t>& track_ids) {
  if (!marginal_prior || marginal_prior->empty()) return;
  MarginalizationTerm term;
  for (auto id : track_ids) {
    const int index = marginal_prior->index_of(landmark_block(tracks.tracks().at(id)));
    if (index >= 0) term.marginalize.push_back(index);
  }
  if (term.marginalize.empty()) return;
  Marginalizer marg;
  for (std::size_t i = 0; i < marginal_prior->blocks.size(); ++i)
    marg.set_manifold(marginal_prior->blocks[i], marginal_prior->kinds[i]);
  term.cost = std::make_shared<MarginalizationFactor>(marginal_prior);
  term.blocks = marginal_prior->blocks;
  marg.add(std::move(term));
  try {
    auto prior = std::make_shared<MarginalizationPrior>(marg.marginalize());
    if (cfg.first_estimates) keep_first_estimates(*prior, *marginal_prior);
    marginal_prior = std::move(prior);
  } catch (const Error&) {
    marginal_prior.reset();
    ++stats.marginalization_failures;
  }
}

void SlidingWindowEstimator::Impl::reanchor_tracks_of(const WindowState& leaving) {
  const SE3 T_W_Cold = T_W_C(leaving);
  for (auto id : tracks.anchored_at(leaving.id)) {
    FeatureTrack& track = tracks.tracks().at(id);
    if (track.handed_over) continue;  // its frozen anchor stays
    if (track.observations.size() < 2) continue;  // disappears with the frame
    const WindowState* next = state(track.observations[1].frame_id);
    if (track.initialized && next) {
      const Vec3 m(track.landmark[0], track.landmark[1], 1.0);
      const Vec3 p_new = T_W_C(*next).inverse() * (T_W_Cold * (m / track.inverse_depth()));
      track.initialized = p_new.z() > kMinFeatureDepth && p_new.z() < kMaxFeatureDepth;
      if (!track.initialized) continue;
      // A fixed bearing is the new anchor's measurement; an estimated one carries the estimate over.
      const Eigen::Vector2d bearing =
          bearing_estimated() ? Eigen::Vector2d(p_new.head<2>() / p_new.z()) : track.observations[1].m;
      track.landmark[0] = bearing.x();
      track.landmark[1] = bearing.y();
      track.inverse_depth() = 1.0 / p_new.z();
    } else {
      track.initialized = false;
    }
  }
}

void SlidingWindowEstimator::Impl::slide_out_oldest() {
  WindowState& oldest = *window.front();
  bool marginalized = false;
  std::vector<std::uint64_t> marginalized_tracks;  // tracks whose landmark went into the prior
  if (cfg.marginalization) {
    // Blocks leaving: the oldest pose and speed-bias, the inverse depths anchored there.
    std::set<const double*> leaving{oldest.pose, oldest.speed_bias};
    if (oldest.has_gps_bias) leaving.insert(oldest.gps_bias);
    // reanchor: the factors of the tracks anchored here that the newest frame still sees stay out
    // of the prior (re-anchored below); the tracks that ended are marginalized whole.
    std::set<const double*> left_out;
    const std::uint64_t newest_id = window.back()->id;
    const std::set<const double*> handed_over =
        cfg.leaving_anchor == LeavingAnchorPolicy::kHandOver ? hand_over_tracks_of(oldest) : std::set<const double*>{};
    for (auto id : tracks.anchored_at(oldest.id)) {
      FeatureTrack& track = tracks.tracks().at(id);
      if (handed_over.count(landmark_block(track))) continue;  // kept, its leaving observation in the prior
      const bool alive = track.observations.back().frame_id == newest_id;
      const bool keep =
          (cfg.leaving_anchor == LeavingAnchorPolicy::kReanchor || cfg.leaving_anchor == LeavingAnchorPolicy::kHandOver) &&
          alive;
      (keep ? left_out : leaving).insert(landmark_block(track));
      if (!keep) marginalized_tracks.push_back(id);
    }
    std::vector<double*> fixed;
    const std::vector<Residual> residuals = build_residuals(nullptr, &fixed);
    Marginalizer marg;
    for (auto& s : window) marg.set_manifold(s->pose, BlockKind::kPose);
    marg.set_manifold(extrinsic, BlockKind::kPose);
    if (!cfg.estimate_extrinsic) marg.set_constant(extrinsic);
    for (double* lambda : fixed) {
      marg.set_constant(lambda);
      leaving.erase(lambda);
    }
    if (!cfg.use_imu)
      for (auto& s : window) marg.set_constant(s->speed_bias);
    if (!cfg.use_imu) leaving.erase(oldest.speed_bias);
    for (const auto& r : residuals) {
      if (std::any_of(r.blocks.begin(), r.blocks.end(), [&](const double* b) { return left_out.count(b) > 0; }))
        continue;
      MarginalizationTerm term;
      for (std::size_t i = 0; i < r.blocks.size(); ++i)
        if (leaving.count(r.blocks[i])) term.marginalize.push_back(static_cast<int>(i));
      if (term.marginalize.empty()) continue;
      term.cost = r.cost;
      term.loss = r.loss;
      term.blocks = r.blocks;
      marg.add(std::move(term));
    }
    try {
      const sliding_window::GatedLoss gated(loss.get(), robust_loss.get(), cfg.prior_weights == CovarianceWeights::kInliers);
      auto prior = std::make_shared<MarginalizationPrior>(marg.marginalize());
      if (cfg.first_estimates && marginal_prior) keep_first_estimates(*prior, *marginal_prior);
      marginal_prior = std::move(prior);
      ++stats.marginalizations;
      marginalized = true;
    } catch (const Error&) {
      // A factor that cannot be linearized here: lose the prior rather than the run, and hold the
      // gauge as without marginalization (below).
      marginal_prior.reset();
      ++stats.marginalization_failures;
    }
    if (state_prior_id == oldest.id) state_prior.reset();  // consumed by the new prior
  }
  if (marginalized && (cfg.leaving_anchor == LeavingAnchorPolicy::kReanchor ||
                       cfg.leaving_anchor == LeavingAnchorPolicy::kHandOver)) {
    // The ended tracks' observations are all in the prior now.
    for (auto id : marginalized_tracks) tracks.erase(id);
    reanchor_tracks_of(oldest);
  } else if (marginalized && cfg.leaving_anchor == LeavingAnchorPolicy::kRestart) {
    // Every observation of these tracks is now in the prior; restart them at their next new
    // observation instead of re-anchoring (which uses those observations again).
    for (auto id : tracks.anchored_at(oldest.id)) tracks.erase(id);
  } else {
    reanchor_tracks_of(oldest);
  }
  tracks.remove_frame(oldest.id);
  window.pop_front();
  window.front()->imu.reset();
  if (!marginalized) {
    // Hold the gauge: pin the new oldest keyframe where the window put it.
    const WindowState& s = *window.front();
    Mat15 P = Mat15::Identity() * kLooseSpeedBiasSigma * kLooseSpeedBiasSigma;
    P.topLeftCorner<6, 6>() = Mat6::Identity() * kPinnedPoseSigma * kPinnedPoseSigma;
    state_prior = std::make_shared<StatePriorFactor>(s.T_W_B(), s.v(), s.b_g(), s.b_a(), P);
    state_prior_id = s.id;
  }
}

StateEstimate SlidingWindowEstimator::Impl::handle_frame(const FeatureFrame& frame) {
  ++stats.frames;
  const Timestamp t = frame.t + camera_to_imu_ns;
  const Timestamp still_ns = static_cast<Timestamp>(std::llround(cfg.still_duration_s * 1e9));
  // The stillness tests look back over the longer of the still window and the zero-velocity span.
  recent_frames.push_back(frame);
  const double keep_s = std::max(cfg.still_duration_s, cfg.zero_velocity_lookback_s) + 0.1;
  while (ns_to_seconds(frame.t - recent_frames.front().t) > keep_s) recent_frames.pop_front();
  if (!initialized && init_method != InitializationMethod::kStill) {
    // A re-initialization of a still start while the user stands still: start still again (a
    // visual initialization needs motion that may not come).
    if (cfg.init_method != InitializationMethod::kStill || !cfg.still_gyro_bias || !still_start_possible(frame, t))
      return collect_for_visual_initialization(frame, t);
    clear_window(/*new_map_frame=*/false);
    init_method = InitializationMethod::kStill;
  }
  if (!initialized) {
    if (imu.empty() || imu.front().t > t - still_ns) return initializing_estimate(frame.t);
    last_estimate = initialize(frame, t);
    return *last_estimate;
  }
  if (t <= window.back()->t) {
    // Camera stamps arrive increasing (handle() checks), so the time offset estimated so far
    // moved: skip the frame, counted, rather than stop the walk.
    if (!last_estimate) throw Error("estimator: feature frames must have increasing time stamps");
    ++stats.frames_out_of_time_order;
    return estimate_of(*window.back(), frame.t, last_estimate->mode, last_estimate->covariance);
  }

  const WindowState& last_kf = *window.back();
  auto s = std::make_unique<WindowState>();
  s->id = next_id++;
  s->t = t;
  s->imu = ImuPreintegration::between(imu, last_kf.t, t, imu_noise, last_kf.b_g(), last_kf.b_a());
  SE3 T;
  Vec3 v;
  s->imu->predict(last_kf.T_W_B(), last_kf.v(), last_kf.b_g(), last_kf.b_a(), &T, &v);
  pose_to_block(T, s->pose);
  s->speed_bias[0] = v.x(), s->speed_bias[1] = v.y(), s->speed_bias[2] = v.z();
  for (int i = 3; i < kSpeedBiasSize; ++i) s->speed_bias[i] = last_kf.speed_bias[i];
  // Zero velocity when the tracks stood still over the look-back and the predicted speed is low (a
  // far scene seen straight ahead barely moves in the image on a slow step; and the IMU sees a
  // start before the image does).
  if (cfg.use_zero_velocity && cfg.use_imu && s->v().norm() <= cfg.zero_velocity_max_speed_mps)
    s->still = still_gyro(frame, t, cfg.zero_velocity_lookback_s, cfg.zero_velocity_max_motion_px);
  stats.zero_velocity_frames += s->still.has_value();
  window.push_back(std::move(s));
  WindowState& newest = *window.back();
  add_observations(newest.id, frame);
  if (cfg.use_gps) attach_gps(newest);
  if (newest.gps && enu_registered && cfg.gps_mode == GpsMode::kJoint && cfg.gps_multipath_fraction > 0)
    start_gps_bias(newest);
  if (cfg.use_mag)
    for (auto& w : window) attach_mag(*w);
  // A frame carrying a fix stays in the window, so that its GPS factor does.
  const bool keyframe = decide_keyframe(*window[window.size() - 2], newest, frame.features.size()) ||
                        (newest.gps && enu_registered);
  return solve_newest(frame, keyframe);
}

StateEstimate SlidingWindowEstimator::Impl::solve_newest(const FeatureFrame& frame, bool keyframe) {
  WindowState& newest = *window.back();
  const Timestamp t = newest.t;
  // Tracks that get their first depth now: the failure test does not judge vision by them until a
  // whole-window solve has estimated their depth (a track triangulated from the first centimetres
  // of a start does not fit a newest-only solve, which holds it).
  for (auto& [id, track] : tracks.tracks())
    if (!track.initialized) fresh_landmarks.insert(track.landmark), fresh_landmarks.insert(&track.inverse_depth());
  initialize_tracks();
  for (auto& [id, track] : tracks.tracks())
    if (!track.initialized) fresh_landmarks.erase(track.landmark), fresh_landmarks.erase(&track.inverse_depth());

  std::optional<NewestCovariance> c;
  // A non-keyframe is dropped after its solve: with non_keyframes=newest it moves alone (a restarted
  // window, still converging, always solves whole).
  const bool newest_only = !keyframe && cfg.non_keyframe_solve == NonKeyframeSolve::kNewest && gaussian_solves == 0;
  const auto solve_start = std::chrono::steady_clock::now();
  const VisualCount count = solve(cfg.covariance_method != CovarianceMethod::kOff ? &c : nullptr, newest_only);
  if (!newest_only) fresh_landmarks.clear();
  frame_stages.solve_ms += ms_since(solve_start) - frame_stages.covariance_ms;
  remove_failed_tracks();
  if (cfg.use_gps && cfg.gps_mode == GpsMode::kJoint) register_gps(newest);
  if (cfg.use_gps && cfg.gps_mode == GpsMode::kDecoupled) reregister_gps(newest);

  EstimatorMode mode;
  // Standing still, the tracks have no parallax to triangulate, but they confirm the stillness
  // that the zero-velocity update holds: vision still supports the state.
  const bool seen_still = newest.still.has_value() && frame.features.size() >= static_cast<std::size_t>(cfg.min_visual_features);
  if (count.features < static_cast<std::size_t>(cfg.min_visual_features) && !seen_still) {
    if (!imu_only_since) imu_only_since = t;
    mode = ns_to_seconds(t - *imu_only_since) > cfg.lost_after_s ? EstimatorMode::kLost : EstimatorMode::kImuOnly;
  } else {
    imu_only_since.reset();
    mode = count.depth_features > 0 ? EstimatorMode::kRgbdVio : EstimatorMode::kVio;
  }
  if (!T_W_C(newest).t.allFinite() || !newest.T_W_B().q.coeffs().allFinite()) mode = EstimatorMode::kLost;

  Mat15 cov;
  if (c) {
    cov = c->state;
  } else {
    if (cfg.covariance_method != CovarianceMethod::kOff) ++stats.covariance_failures;
    // No covariance from this window: the last one, inflated (never pretend to more certainty),
    // up to the "unknown" level.
    cov = last_estimate ? Mat15(last_estimate->covariance * 1.5) : Mat15(Mat15::Identity() * kUnknownVariance);
    const double largest = cov.diagonal().maxCoeff();
    if (largest > kUnknownVariance) cov *= kUnknownVariance / largest;
  }
  StateEstimate e = estimate_of(newest, frame.t, mode, cov);
  if (enu_registered) {
    e.T_ENU_W = enu_alignment_from_block(enu_alignment);
    if (c && c->enu_alignment) {
      e.T_ENU_W_covariance = *c->enu_alignment;
    } else if (enu_prior) {  // registered after this frame's solve: the registration's covariance
      e.T_ENU_W_covariance = Mat4(enu_prior->information().inverse());
    }
  } else if (decoupled_T_ENU_W) {
    e.T_ENU_W = *decoupled_T_ENU_W;
    e.T_ENU_W_covariance = decoupled_covariance;
  }
  if (cfg.failure_detection) {
    // A restarted frame's state is carried from the good estimate, not solved: no jump to check.
    const StateEstimate* previous = last_estimate && last_estimate->mode != EstimatorMode::kInitializing && !restarting
                                        ? &*last_estimate
                                        : nullptr;
    VisualSupport support = count.newest;
    record_inlier_share(e.t, support);
    std::optional<std::string> why = count.solver_failed ? std::optional<std::string>("solver failed")
                                                         : detect_estimator_failure(e, previous, support, cfg.failure);
    if (why) return recover(frame, *why);
    if (count.newest.residuals >= static_cast<std::size_t>(cfg.failure.min_visual_residuals) &&
        count.newest.inlier_fraction() >= cfg.confirmed_inlier_fraction)
      confirm(e);
  }
  last_estimate = e;

  if (keyframe) {
    newest.keyframe = true;
    ++stats.keyframes;
    frame_stages.keyframe = true;
    if (static_cast<int>(window.size()) > cfg.window_size) {
      const auto start = std::chrono::steady_clock::now();
      slide_out_oldest();
      frame_stages.marginalization_ms = ms_since(start);
    }
  } else {
    tracks.remove_frame(newest.id);
    window.pop_back();
  }
  const Timestamp mag_keep_from = window.front()->t - seconds_to_ns(1.0);
  while (!mag.empty() && mag.front().t < mag_keep_from) mag.pop_front();
  return e;
}

// ---------------------------------------------------------------------------------------------

SlidingWindowEstimator::SlidingWindowEstimator(const RigCalibration& rig, const EstimatorConfig& config,
                                               const std::string& camera_name,
                                               const std::optional<GeodeticOrigin>& origin)
    : impl_(std::make_unique<Impl>(rig, config, camera_name, origin)) {}
SlidingWindowEstimator::~SlidingWindowEstimator() = default;
SlidingWindowEstimator::SlidingWindowEstimator(const SlidingWindowEstimator& other)
    : impl_(std::make_unique<Impl>(*other.impl_)) {}
SlidingWindowEstimator::SlidingWindowEstimator(SlidingWindowEstimator&&) noexcept = default;
SlidingWindowEstimator& SlidingWindowEstimator::operator=(SlidingWindowEstimator&&) noexcept = default;

std::vector<StateEstimate> SlidingWindowEstimator::process(const SensorEvent& event) { return impl_->process(event); }

std::vector<StateEstimate> SlidingWindowEstimator::finish() {
  std::vector<StateEstimate> out;
  impl_->stage_times.assign(impl_->pending.size(), FrameStageTimes{});
  for (const auto& f : impl_->pending) {
    ++impl_->stats.frames;
    StateEstimate e;
    if (impl_->last_estimate) e = *impl_->last_estimate;
    else e.covariance = Mat15::Identity() * kUnknownVariance;
    e.t = f.t;
    e.mode = EstimatorMode::kLost;
    out.push_back(e);
  }
  impl_->pending.clear();
  return out;
}

std::size_t SlidingWindowEstimator::optimize() {
  if (impl_->window.empty()) return 0;
  return impl_->solve().all_features;
}

const EstimatorConfig& SlidingWindowEstimator::config() const { return impl_->cfg; }
SE3 SlidingWindowEstimator::camera_extrinsic() const { return pose_from_block(impl_->extrinsic); }
double SlidingWindowEstimator::camera_time_offset_s() const { return impl_->time_offset[0]; }
const EstimatorStatistics& SlidingWindowEstimator::statistics() const { return impl_->stats; }
const std::vector<FrameStageTimes>& SlidingWindowEstimator::stage_times() const { return impl_->stage_times; }
std::size_t SlidingWindowEstimator::window_keyframes() const {
  std::size_t n = 0;
  for (const auto& s : impl_->window) n += s->keyframe ? 1 : 0;
  return n;
}

}  // namespace navaid::estimation
