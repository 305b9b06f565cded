// Visual-inertial alignment: exact on windows whose IMU samples integrate (by the preintegration's
// own mid-point scheme) to the true keyframe states, bounded with IMU noise and pose errors,
// up-to-scale windows, failures with reasons, malformed input; and the whole initialization
// (window SfM + alignment) on a simulated walk that starts moving, against its ground truth.
#include "navaid/estimation/initialization/visual_inertial_alignment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/estimation/initialization/window_sfm.hpp"
#include "estimator_fixtures.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

constexpr Timestamp kStep = 5'000'000;  // 200 Hz
constexpr int kSamplesPerKeyframe = 40;  // 0.2 s between keyframes

struct WindowSpec {
  std::size_t keyframes = 10;
  Vec3 gyro_bias = Vec3(0.012, -0.02, 0.008);
  double gyro_sigma = 0, accel_sigma = 0;  // per-sample white noise
  unsigned seed = 1;
};

struct Window {
  std::vector<ImuSample> imu;
  std::vector<Timestamp> times;
  std::vector<SE3> T_W_B;  // true keyframe states
  std::vector<Vec3> v_W;
  SE3 T_B_C;
};

// The true motion is integrated from the noise-free samples with the preintegration's mid-point
// scheme in W, so that preintegrating the measured samples at the true bias gives back the true
// keyframe states to round-off.
Window make_window(const WindowSpec& s) {
  std::mt19937 rng(s.seed);
  std::normal_distribution<double> n01(0, 1);
  auto omega = [](double t) { return Vec3(0.3 * std::sin(1.3 * t), 0.4 * std::cos(0.9 * t), 0.5 * std::sin(0.7 * t + 0.3)); };
  auto accel_W = [](double t) { return Vec3(0.5 * std::sin(1.1 * t), 0.4 * std::cos(1.7 * t), 0.2 * std::sin(2.3 * t)); };
  Window w;
  w.T_B_C = SE3(quat_from_rpy(-M_PI / 2, 0.05, -M_PI / 2), Vec3(0.05, 0.01, -0.02));
  const Timestamp t0 = 1'000'000'000;
  Quat R = quat_from_rpy(0.1, -0.2, 0.7);
  Vec3 p(1.0, 2.0, 0.5), v(0.8, -0.3, 0.1);  // a moving start
  const int samples = static_cast<int>(s.keyframes - 1) * kSamplesPerKeyframe;
  Vec3 w_prev = Vec3::Zero(), a_prev = Vec3::Zero();
  for (int k = 0; k <= samples; ++k) {
    const Timestamp t = t0 + k * kStep;
    const double ts = ns_to_seconds(t - t0);
    const Vec3 w_true = omega(ts);
    if (k > 0) {
      const double h = ns_to_seconds(kStep);
      const Quat R_next = so3_boxplus(R, 0.5 * (w_prev + w_true) * h);
      const Vec3 a_true = R_next.conjugate() * (accel_W(ts) - kGravityW);
      const Vec3 a = 0.5 * (R * a_prev + R_next * a_true) + kGravityW;
      p += v * h + 0.5 * a * h * h;
      v += a * h;
      R = R_next;
      a_prev = a_true;
    } else {
      a_prev = R.conjugate() * (accel_W(ts) - kGravityW);
    }
    w_prev = w_true;
    ImuSample m;
    m.t = t;
    m.gyro = w_true + s.gyro_bias + s.gyro_sigma * draw_vector<3>([&] { return n01(rng); });
    m.accel = a_prev + s.accel_sigma * draw_vector<3>([&] { return n01(rng); });
    w.imu.push_back(m);
    if (k % kSamplesPerKeyframe == 0) {
      w.times.push_back(t);
      w.T_W_B.emplace_back(R, p);
      w.v_W.push_back(v);
    }
  }
  return w;
}

ImuNoise noise() { return ImuNoise::from(navaid::testing::euroc_imu_calibration()); }

std::vector<ImuPreintegration> preintegrate(const std::vector<ImuSample>& imu, const std::vector<Timestamp>& times) {
  std::vector<ImuPreintegration> pre;
  for (std::size_t k = 0; k + 1 < times.size(); ++k)
    pre.push_back(ImuPreintegration::between(imu, times[k], times[k + 1], noise(), Vec3::Zero(), Vec3::Zero()));
  return pre;
}

// Camera poses in the frame of keyframe `l`'s camera, as a window SfM gives them.
std::vector<SE3> camera_poses(const std::vector<SE3>& T_W_B, const SE3& T_B_C, std::size_t l) {
  const SE3 T_l_W = (T_W_B[l] * T_B_C).inverse();
  std::vector<SE3> T_l_C;
  for (const auto& T : T_W_B) T_l_C.push_back(T_l_W * T * T_B_C);
  return T_l_C;
}

struct StateErrors {
  double position_m = 0;     // of T_W_B[0]^-1 T_W_B[k]
  double rotation_rad = 0;   // likewise
  double gravity_rad = 0;    // direction of gravity seen from each body
  double velocity_mps = 0;   // body-frame velocity
};

// The alignment's W differs from the truth's by yaw and translation: compare what does not see them.
StateErrors state_errors(const VisualInertialAlignment& a, const std::vector<SE3>& T_W_B, const std::vector<Vec3>& v_W) {
  StateErrors e;
  for (std::size_t k = 0; k < T_W_B.size(); ++k) {
    const SE3 rel = a.T_W_B[0].inverse() * a.T_W_B[k], rel_true = T_W_B[0].inverse() * T_W_B[k];
    e.position_m = std::max(e.position_m, (rel.t - rel_true.t).norm());
    e.rotation_rad = std::max(e.rotation_rad, rel.q.angularDistance(rel_true.q));
    const Vec3 down = a.T_W_B[k].q.conjugate() * Vec3::UnitZ(), down_true = T_W_B[k].q.conjugate() * Vec3::UnitZ();
    e.gravity_rad = std::max(e.gravity_rad, std::acos(std::clamp(down.dot(down_true), -1.0, 1.0)));
    const Vec3 vb = a.T_W_B[k].q.conjugate() * a.v_W[k], vb_true = T_W_B[k].q.conjugate() * v_W[k];
    e.velocity_mps = std::max(e.velocity_mps, (vb - vb_true).norm());
  }
  return e;
}

TEST(VisualInertialAlignment, ExactWindowGivesTheTrueStates) {
  const WindowSpec spec;
  const Window w = make_window(spec);
  const std::size_t l = 3;
  const auto T_l_C = camera_poses(w.T_W_B, w.T_B_C, l);
  const auto a = align_visual_inertial(w.times, T_l_C, w.T_B_C, preintegrate(w.imu, w.times));
  ASSERT_TRUE(a.success) << a.failure;
  EXPECT_LT((a.gyro_bias - spec.gyro_bias).norm(), 1e-6);
  EXPECT_LT(a.gyro_rms_rad, 1e-8);
  EXPECT_DOUBLE_EQ(a.scale, 1.0);
  const SE3 T_l_W = (w.T_W_B[l] * w.T_B_C).inverse();
  EXPECT_LT((a.gravity_l - T_l_W.q * kGravityW).norm(), 1e-6);
  EXPECT_LT((a.gravity_l_unrefined - T_l_W.q * kGravityW).norm(), 1e-6);
  ASSERT_EQ(a.velocities_l.size(), w.times.size());
  for (std::size_t k = 0; k < w.times.size(); ++k)
    EXPECT_LT((a.velocities_l[k] - T_l_W.q * w.v_W[k]).norm(), 1e-6) << k;
  // W: gravity -z, the oldest body at the origin with yaw 0.
  EXPECT_LT((a.T_W_l.q * a.gravity_l - kGravityW).norm(), 1e-9);
  EXPECT_LT(a.T_W_B[0].t.norm(), 1e-12);
  EXPECT_NEAR(yaw_of(a.T_W_B[0].q), 0.0, 1e-12);
  for (std::size_t k = 0; k < w.times.size(); ++k)
    EXPECT_TRUE((a.T_W_l * T_l_C[k] * w.T_B_C.inverse()).is_approx(a.T_W_B[k], 1e-9)) << "T_W_l agrees, " << k;
  const StateErrors e = state_errors(a, w.T_W_B, w.v_W);
  EXPECT_LT(e.position_m, 1e-6);
  EXPECT_LT(e.rotation_rad, 1e-6);
  EXPECT_LT(e.gravity_rad, 1e-6);
  EXPECT_LT(e.velocity_mps, 1e-6);
  // The returned preintegrations are linearized at the estimate.
  ASSERT_EQ(a.preintegrations.size(), w.times.size() - 1);
  EXPECT_LT((a.preintegrations[0].linearization_gyro_bias() - a.gyro_bias).norm(), 1e-15);
}

TEST(VisualInertialAlignment, UpToScaleWindowRecoversTheScale) {
  const Window w = make_window({});
  auto T_l_C = camera_poses(w.T_W_B, w.T_B_C, 0);
  const double sfm_units = 0.37;  // SfM translation per metre
  for (auto& T : T_l_C) T.t *= sfm_units;
  VisualInertialAlignmentOptions o;
  o.estimate_scale = true;
  const auto a = align_visual_inertial(w.times, T_l_C, w.T_B_C, preintegrate(w.imu, w.times), o);
  ASSERT_TRUE(a.success) << a.failure;
  EXPECT_NEAR(a.scale, 1.0 / sfm_units, 1e-6);
  const StateErrors e = state_errors(a, w.T_W_B, w.v_W);
  EXPECT_LT(e.position_m, 1e-6);
  EXPECT_LT(e.velocity_mps, 1e-6);
  EXPECT_LT(e.gravity_rad, 1e-6);
}

// EuRoC-grade IMU noise (per sample: 1.7e-4 rad/s * sqrt(200), 2e-3 m/s^2 * sqrt(200)) and
// visual poses perturbed by 2 mrad and 5 mm (what the noisy window SfM reaches). Largest errors
// measured over the 10 seeds: bias 3.7e-3 rad/s, gravity 8.6 mrad, velocity 0.027 m/s; the
// bounds leave about 2x margin.
TEST(VisualInertialAlignment, NoisyWindowsStayWithinBounds) {
  const auto cal = navaid::testing::euroc_imu_calibration();
  for (unsigned seed = 1; seed <= 10; ++seed) {
    WindowSpec spec;
    spec.seed = seed;
    spec.gyro_sigma = cal.gyro_noise_density * std::sqrt(cal.rate_hz);
    spec.accel_sigma = cal.accel_noise_density * std::sqrt(cal.rate_hz);
    const Window w = make_window(spec);
    auto T_l_C = camera_poses(w.T_W_B, w.T_B_C, 0);
    std::mt19937 rng(100 + seed);
    std::normal_distribution<double> n01(0, 1);
    for (std::size_t k = 1; k < T_l_C.size(); ++k) {
      T_l_C[k].q = so3_boxplus(T_l_C[k].q, 0.002 * draw_vector<3>([&] { return n01(rng); }));
      T_l_C[k].t += 0.005 * draw_vector<3>([&] { return n01(rng); });
    }
    const auto a = align_visual_inertial(w.times, T_l_C, w.T_B_C, preintegrate(w.imu, w.times));
    ASSERT_TRUE(a.success) << "seed " << seed << ": " << a.failure;
    EXPECT_LT((a.gyro_bias - spec.gyro_bias).norm(), 0.008) << "seed " << seed;
    const StateErrors e = state_errors(a, w.T_W_B, w.v_W);
    EXPECT_LT(e.gravity_rad, 0.02) << "seed " << seed;
    EXPECT_LT(e.velocity_mps, 0.06) << "seed " << seed;
    EXPECT_NEAR(a.gravity_l.norm(), kGravityW.norm(), 1e-9);
  }
}

TEST(VisualInertialAlignment, DegenerateWindowsFailWithAReason) {
  const Window w = make_window({});
  const auto T_l_C = camera_poses(w.T_W_B, w.T_B_C, 0);
  const auto pre = preintegrate(w.imu, w.times);
  {
    const std::vector<Timestamp> t(w.times.begin(), w.times.begin() + 3);
    const std::vector<SE3> T(T_l_C.begin(), T_l_C.begin() + 3);
    const std::vector<ImuPreintegration> p(pre.begin(), pre.begin() + 2);
    const auto a = align_visual_inertial(t, T, w.T_B_C, p);
    EXPECT_FALSE(a.success);
    EXPECT_NE(a.failure.find("too few keyframes"), std::string::npos) << a.failure;
  }
  {
    // An accelerometer that reads 30 % high.
    auto imu = w.imu;
    for (auto& s : imu) s.accel *= 1.3;
    const auto a = align_visual_inertial(w.times, T_l_C, w.T_B_C, preintegrate(imu, w.times));
    EXPECT_FALSE(a.success);
    EXPECT_NE(a.failure.find("gravity norm"), std::string::npos) << a.failure;
  }
  {
    WindowSpec spec;
    spec.gyro_bias = Vec3(0.3, 0.0, -0.1);
    const Window wb = make_window(spec);
    const auto a = align_visual_inertial(wb.times, camera_poses(wb.T_W_B, wb.T_B_C, 0), wb.T_B_C,
                                         preintegrate(wb.imu, wb.times));
    EXPECT_FALSE(a.success);
    EXPECT_NE(a.failure.find("implausible gyro bias"), std::string::npos) << a.failure;
  }
}

TEST(VisualInertialAlignment, MalformedInputThrows) {
  using navaid::testing::error_message;
  const Window w = make_window({});
  const auto T_l_C = camera_poses(w.T_W_B, w.T_B_C, 0);
  const auto pre = preintegrate(w.imu, w.times);
  const std::vector<SE3> fewer(T_l_C.begin(), T_l_C.end() - 1);
  EXPECT_NE(error_message<Error>([&] { align_visual_inertial(w.times, fewer, w.T_B_C, pre); }).find("camera poses"),
            std::string::npos);
  const std::vector<ImuPreintegration> short_pre(pre.begin(), pre.end() - 1);
  EXPECT_NE(error_message<Error>([&] { align_visual_inertial(w.times, T_l_C, w.T_B_C, short_pre); })
                .find("preintegrations"),
            std::string::npos);
  auto shifted = w.times;
  shifted[4] += 1'000'000;
  EXPECT_NE(error_message<Error>([&] { align_visual_inertial(shifted, T_l_C, w.T_B_C, pre); }).find("does not run"),
            std::string::npos);
  auto nan_pose = T_l_C;
  nan_pose[2].t.x() = std::nan("");
  EXPECT_NE(error_message<Error>([&] { align_visual_inertial(w.times, nan_pose, w.T_B_C, pre); }).find("not finite"),
            std::string::npos);
  VisualInertialAlignmentOptions o;
  o.max_gyro_bias = 0;
  const auto e = navaid::testing::expect_throw<ConfigError>([&] { align_visual_inertial(w.times, T_l_C, w.T_B_C, pre, o); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "max_gyro_bias");
}

// --- the whole initialization on a simulated walk ---

using testing::groundtruth_at;

const GroundTruthState& nearest(const std::vector<GroundTruthState>& gt, Timestamp t) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const GroundTruthState& s, Timestamp x) { return s.t < x; });
  if (it == gt.end()) return gt.back();
  if (it != gt.begin() && t - std::prev(it)->t < it->t - t) return *std::prev(it);
  return *it;
}

// lab-walk-1 with the hand mount, walking from the first sample (no still start), a gyro bias of
// 0.028 rad/s; 10 keyframes 0.2 s apart (every third frame at 15 Hz) from 1 s into the walk.
struct SimulatedWindow {
  io::Recording rec;
  CameraCalibration cam;
  std::vector<SfmKeyframe> keyframes;
  std::vector<Timestamp> times;  // IMU clock
  std::vector<SE3> T_W_B;        // ground truth at the keyframes
  std::vector<Vec3> v_W;
  Vec3 b_g = Vec3::Zero();
  std::vector<ImuPreintegration> preintegrations;  // at zero biases
};

const SimulatedWindow& simulated_window() {
  static const SimulatedWindow w = [] {
    SimulatedWindow s;
    s.rec = testing::simulate_recording(
        "vinit_moving_start", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=4",
                               "seed=5", "simulation.still_time=0", "sensor.camera.rate=15",
                               "features.max_per_frame=120", "sensor.imu.initial_gyro_bias=[0.02, -0.015, 0.012]"});
    s.cam = s.rec.calibration.cameras.front();
    const auto model = make_camera_model(s.cam);
    const Timestamp t_start = s.rec.features.front().t + seconds_to_ns(1.0);
    for (std::size_t i = 0; i < s.rec.features.size() && s.keyframes.size() < 10; ++i) {
      const FeatureFrame& f = s.rec.features[i];
      if (f.t < t_start || (i % 3) != 0) continue;
      SfmKeyframe kf;
      for (const auto& o : f.features)
        if (const auto m = model->undistort(model->distorted_from_pixel(o.uv)))
          kf.observations.push_back({o.track_id, *m, o.depth_m});
      s.keyframes.push_back(kf);
      s.times.push_back(f.t + seconds_to_ns(s.cam.time_offset_s));
    }
    for (const Timestamp t : s.times) {
      s.T_W_B.push_back(groundtruth_at(s.rec.groundtruth, t));
      s.v_W.push_back(nearest(s.rec.groundtruth, t).v_W.value_or(Vec3::Constant(NAN)));
    }
    s.b_g = nearest(s.rec.groundtruth, s.times.front()).b_g.value_or(Vec3::Constant(NAN));
    const ImuNoise n = ImuNoise::from(*s.rec.calibration.imu);
    for (std::size_t k = 0; k + 1 < s.times.size(); ++k)
      s.preintegrations.push_back(
          ImuPreintegration::between(s.rec.imu, s.times[k], s.times[k + 1], n, Vec3::Zero(), Vec3::Zero()));
    return s;
  }();
  return w;
}

WindowSfmOptions simulated_sfm_options(const CameraCalibration& cam) {
  WindowSfmOptions o;
  o.focal_px = cam.fx;
  o.pixel_sigma_px = 1.0;  // features.pixel_sigma
  o.inverse_depth_sigma = cam.depth_disparity_sigma_px / (cam.fx * cam.depth_baseline_m);
  o.pose_change.ransac_threshold_px = 2.0;
  return o;
}

// Measured on this window: SfM 2.1 mrad / 11 mm, bias error 0.95e-3 rad/s (the bias itself is
// 0.028 rad/s), gravity 2.6 mrad, velocity 0.019 m/s, relative position 11 mm. Bounds ~4x.
TEST(Initialization, SimulatedMovingStartRecoversBiasVelocityAndGravity) {
  const SimulatedWindow& w = simulated_window();
  ASSERT_EQ(w.keyframes.size(), 10u);
  EXPECT_GT(w.v_W.front().norm(), 0.3) << "the window must start moving";
  EXPECT_LT((w.b_g - Vec3(0.02, -0.015, 0.012)).norm(), 2e-3);

  const WindowSfm sfm = solve_window_sfm(w.keyframes, simulated_sfm_options(w.cam));
  ASSERT_TRUE(sfm.success) << sfm.failure;
  EXPECT_FALSE(sfm.up_to_scale);
  const auto T_l_C_true = camera_poses(w.T_W_B, w.cam.T_B_C, sfm.reference);
  double sfm_rot = 0, sfm_pos = 0;
  for (std::size_t k = 0; k < w.times.size(); ++k) {
    sfm_rot = std::max(sfm_rot, sfm.T_l_C[k].q.angularDistance(T_l_C_true[k].q));
    sfm_pos = std::max(sfm_pos, (sfm.T_l_C[k].t - T_l_C_true[k].t).norm());
  }
  EXPECT_LT(sfm_rot, 0.008);
  EXPECT_LT(sfm_pos, 0.04);

  const auto a = align_visual_inertial(w.times, sfm.T_l_C, w.cam.T_B_C, w.preintegrations);
  ASSERT_TRUE(a.success) << a.failure;
  EXPECT_LT((a.gyro_bias - w.b_g).norm(), 4e-3) << a.gyro_bias.transpose() << " vs " << w.b_g.transpose();
  const StateErrors e = state_errors(a, w.T_W_B, w.v_W);
  EXPECT_LT(e.gravity_rad, 0.012);
  EXPECT_LT(e.velocity_mps, 0.08);
  EXPECT_LT(e.position_m, 0.045);

  // The points, through T_W_l as docs/initialization.md tells the estimator: their depth in each
  // keyframe that sees them against the true landmark's (measured median 1 %).
  std::map<std::uint64_t, Vec3> landmarks;
  for (const auto& lm : w.rec.landmarks) landmarks[lm.id] = lm.p_W;
  std::vector<double> rel;
  for (std::size_t k = 0; k < w.times.size(); ++k)
    for (const auto& o : w.keyframes[k].observations) {
      const auto it = sfm.points_l.find(o.track_id);
      if (it == sfm.points_l.end()) continue;
      const Vec3 P_W = a.T_W_l * (a.scale * it->second);
      const double z = ((a.T_W_B[k] * w.cam.T_B_C).inverse() * P_W).z();
      const double z_true = ((w.T_W_B[k] * w.cam.T_B_C).inverse() * landmarks.at(o.track_id)).z();
      rel.push_back(std::abs(z - z_true) / z_true);
    }
  ASSERT_GT(rel.size(), 200u);
  std::nth_element(rel.begin(), rel.begin() + static_cast<long>(rel.size() / 2), rel.end());
  EXPECT_LT(rel[rel.size() / 2], 0.04);
}

// VIO mode: the same window without depth gives an up-to-scale SfM; the alignment estimates the
// scale from the accelerometer. Measured: scale 3 % low, bias error 3.2e-3 rad/s, gravity
// 3.4 mrad, velocity 0.05 m/s.
TEST(Initialization, SimulatedWindowWithoutDepthEstimatesTheScale) {
  const SimulatedWindow& w = simulated_window();
  auto keyframes = w.keyframes;
  for (auto& kf : keyframes)
    for (auto& o : kf.observations) o.depth_m.reset();
  const WindowSfm sfm = solve_window_sfm(keyframes, simulated_sfm_options(w.cam));
  ASSERT_TRUE(sfm.success) << sfm.failure;
  EXPECT_TRUE(sfm.up_to_scale);
  VisualInertialAlignmentOptions o;
  o.estimate_scale = true;
  const auto a = align_visual_inertial(w.times, sfm.T_l_C, w.cam.T_B_C, w.preintegrations, o);
  ASSERT_TRUE(a.success) << a.failure;
  const SE3 T_l_n = (w.T_W_B[sfm.reference] * w.cam.T_B_C).inverse() * (w.T_W_B.back() * w.cam.T_B_C);
  const double scale_true = T_l_n.t.norm() / sfm.T_l_C.back().t.norm();
  const StateErrors e = state_errors(a, w.T_W_B, w.v_W);
  EXPECT_NEAR(a.scale / scale_true, 1.0, 0.1);
  EXPECT_LT((a.gyro_bias - w.b_g).norm(), 8e-3);
  EXPECT_LT(e.gravity_rad, 0.02);
  EXPECT_LT(e.velocity_mps, 0.15);
}

}  // namespace
}  // namespace navaid::estimation
