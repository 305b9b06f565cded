// The front end on rendered images with exact ground truth (simulator: lab-walk-1, hand mount,
// Structure Core camera at 640x480, 30 Hz, default RGB-D noise, no moving people).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/estimation/frontend/feature_tracker.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/rgbd_noise_model.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/sensor_rig.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::estimation {
namespace {

using simulation::RayCaster;

struct Sequence {
  std::unique_ptr<RayCaster> caster;
  std::shared_ptr<const CameraModel> camera;
  simulation::RgbdNoiseConfig noise;
  std::vector<SE3> T_W_C;
  std::vector<RgbdFrame> frames;  // noisy intensity and depth
};

constexpr double kRate = 30.0;

Sequence render(const std::vector<SE3>& poses, std::unique_ptr<RayCaster> caster, const CameraCalibration& calib) {
  Sequence s;
  s.caster = std::move(caster);
  s.camera = make_camera_model(calib);
  s.noise = simulation::rgbd_noise_config(calib);
  const simulation::RgbdRenderer renderer(*s.caster, *s.camera);
  simulation::RenderOptions options;
  options.render_labels = false;
  options.max_depth = 2.0 * calib.depth_max_m;  // the noise model applies the sensor range
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const simulation::RenderedFrame clean = renderer.render(poses[k], options);
    simulation::NoisyRgbd noisy = simulation::apply_rgbd_noise(clean, s.noise, 11, k);
    RgbdFrame f;
    f.t = static_cast<Timestamp>(std::llround(1e9 * static_cast<double>(k) / kRate));
    f.index = k;
    f.intensity = std::move(noisy.intensity);
    f.depth = std::move(noisy.depth);
    s.frames.push_back(std::move(f));
  }
  s.T_W_C = poses;
  return s;
}

CameraCalibration structure_core() {
  return simulation::rescale_camera(simulation::sensor_preset("structure-core").camera, 640, 480);
}

// 16 frames of walking at cruise speed.
const Sequence& walk() {
  static const Sequence s = [] {
    simulation::ScenarioOptions so;
    so.people = so.vehicles = false;
    const simulation::Scenario scenario = simulation::make_scenario("lab-walk-1", so);
    const simulation::Mount mount = simulation::mount_preset("hand");
    simulation::WalkerConfig walker = mount.apply(simulation::WalkerConfig{});
    walker.ground_z_m = scenario.ground_z_m;
    const simulation::WalkerTrajectory trajectory(scenario.path, walker);
    std::vector<SE3> poses;
    for (int k = 0; k < 16; ++k) poses.push_back(trajectory.state(4.0 + k / kRate).T_W_B * mount.T_B_C());
    return render(poses, std::make_unique<RayCaster>(scenario.world), structure_core());
  }();
  return s;
}

// Pure rotation (panning about the camera's vertical axis) by `step_rad` per frame.
const Sequence& pan(double step_rad) {
  static std::map<double, Sequence> cache;
  auto it = cache.find(step_rad);
  if (it != cache.end()) return it->second;
  simulation::ScenarioOptions so;
  so.people = so.vehicles = false;
  const simulation::Scenario scenario = simulation::make_scenario("lab-walk-1", so);
  const SE3 start = walk().T_W_C.front();
  std::vector<SE3> poses;
  for (int k = 0; k < 3; ++k)
    poses.push_back(start * SE3(Quat(Eigen::AngleAxisd(k * step_rad, Vec3::UnitY())), Vec3::Zero()));
  return cache.emplace(step_rad, render(poses, std::make_unique<RayCaster>(scenario.world), structure_core())).first->second;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// Point seen at pixel uv from pose T_W_C (ray cast on the true geometry).
std::optional<Vec3> surface_point(const Sequence& s, const SE3& T_W_C, const Eigen::Vector2d& uv) {
  const std::optional<Vec3> ray = s.camera->unproject(uv);
  if (!ray) return std::nullopt;
  const auto hit = s.caster->cast(T_W_C.t, T_W_C.q * ray->normalized());
  if (!hit) return std::nullopt;
  return hit->point;
}

Eigen::Matrix3d R_cur_prev(const Sequence& s, std::size_t k) {
  return (s.T_W_C[k].q.conjugate() * s.T_W_C[k - 1].q).toRotationMatrix();
}

// Reprojection error of every tracked observation: the first observation of each track is
// back-projected with the true depth (ray cast from the true pose) and re-projected into the
// current true pose.
struct TrackAccuracy {
  std::vector<double> errors;  // [px]
  std::size_t tracked_last = 0;
};

TrackAccuracy track_accuracy(const Sequence& s, const FrontendConfig& config, bool gyro,
                             FeatureTracker::TrackHook hook = {}) {
  FeatureTracker tracker(s.camera, config);
  if (hook) tracker.set_track_hook(std::move(hook));
  std::map<std::uint64_t, Vec3> first_point;  // track id -> true 3D point of its first observation
  TrackAccuracy acc;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const FeatureFrame out = k > 0 && gyro ? tracker.track(s.frames[k], R_cur_prev(s, k)) : tracker.track(s.frames[k]);
    const SE3 T_C_W = s.T_W_C[k].inverse();
    for (const FeatureObservation& o : out.features) {
      const auto it = first_point.find(o.track_id);
      if (it == first_point.end()) {
        if (const auto p = surface_point(s, s.T_W_C[k], o.uv)) first_point.emplace(o.track_id, *p);
        continue;
      }
      const auto predicted = s.camera->project(T_C_W * it->second);
      if (predicted) acc.errors.push_back((o.uv - *predicted).norm());
    }
    acc.tracked_last = tracker.stats().tracked;
  }
  return acc;
}

TEST(FrontendTracking, TracksFollowTheTrueSurfacePoints) {
  const Sequence& s = walk();
  FrontendConfig junctions;  // corners allowed on occlusion junctions
  junctions.depth_edge_margin_px = 0;
  FrontendConfig unchecked;  // frame-to-frame KLT alone
  unchecked.drift_check_interval = 0;
  const struct {
    const char* name;
    FrontendConfig config;
    bool gyro;
  } runs[] = {{"default", FrontendConfig{}, false}, {"gyro prediction", FrontendConfig{}, true},
              {"corners on depth edges", junctions, false}, {"without the drift check", unchecked, false}};
  double p95_default = 0;
  for (const auto& run : runs) {
    const TrackAccuracy acc = track_accuracy(s, run.config, run.gyro);
    ASSERT_GT(acc.errors.size(), 1000u) << run.name;
    const double median = quantile(acc.errors, 0.5), p95 = quantile(acc.errors, 0.95);
    const double within2 =
        static_cast<double>(std::count_if(acc.errors.begin(), acc.errors.end(), [](double e) { return e <= 2.0; })) /
        static_cast<double>(acc.errors.size());
    std::cout << "[ tracking ] " << run.name << ": " << acc.errors.size() << " observations over " << s.frames.size()
              << " frames, error median " << median << " px, p95 " << p95 << " px, max " << quantile(acc.errors, 1.0)
              << " px, within 2 px " << within2 << "; tracked in the last frame " << acc.tracked_last << "\n";
    if (run.config.depth_edge_margin_px == 0) {
      // Junction corners slide along the occluding edge: the reason for the margin.
      EXPECT_GT(p95, 1.5 * p95_default);
      continue;
    }
    if (!run.gyro) p95_default = p95;
    EXPECT_LT(median, 0.5) << run.name;
    EXPECT_LT(p95, 2.0) << run.name;
    EXPECT_GT(within2, 0.95) << run.name;
    EXPECT_GT(acc.tracked_last, 100u) << run.name;  // of 150: walking at 30 Hz loses few tracks per frame
  }
}

TEST(FrontendTracking, TheDriftCheckPullsDriftingTracksBackToTheirBirthPatch) {
  // Every track slides 0.3 px to the right per frame after KLT (a drift frame-to-frame tracking
  // cannot see: each step starts where the last one ended). Without the check the error grows
  // with age to 4.5 px in 16 frames; aligning the birth patch every 5 frames moves the tracks
  // back, so the error stays within the 1.5 px gathered between two checks.
  const Sequence& s = walk();
  const auto slide = [](const std::vector<std::uint64_t>&, std::vector<Eigen::Vector2d>& uv) {
    for (auto& p : uv) p.x() += 0.3;
  };
  FrontendConfig checked;
  checked.drift_check_interval = 5;
  checked.drift_max_px = 2.0;
  FrontendConfig unchecked;
  unchecked.drift_check_interval = 0;
  const TrackAccuracy without = track_accuracy(s, unchecked, false, slide);
  const TrackAccuracy with = track_accuracy(s, checked, false, slide);
  ASSERT_GT(with.errors.size(), 1000u);
  std::cout << "[ tracking ] sliding 0.3 px/frame: p95 " << quantile(without.errors, 0.95) << " px unchecked, "
            << quantile(with.errors, 0.95) << " px with the drift check\n";
  EXPECT_GT(quantile(without.errors, 0.95), 3.0);
  EXPECT_LT(quantile(with.errors, 0.95), 2.0);
  EXPECT_LT(quantile(with.errors, 0.5), 1.0);

  // A jump beyond drift_max_px (the hook moves every track 3 px at once) drops the tracks due.
  FeatureTracker tracker(s.camera, checked);
  int frame = 0;
  tracker.set_track_hook([&](const std::vector<std::uint64_t>&, std::vector<Eigen::Vector2d>& uv) {
    if (++frame == 4)
      for (auto& p : uv) p.y() += 3.0;
  });
  std::size_t rejected = 0, corrected = 0, checks = 0;
  for (std::size_t k = 0; k < 6; ++k) {
    tracker.track(s.frames[k]);
    rejected += tracker.stats().rejected_drift;
    corrected += tracker.stats().drift_corrected;
    checks += tracker.stats().drift_checked;
  }
  EXPECT_GT(rejected, 100u);  // the first frame's corners, due at age 5
  EXPECT_GE(checks, rejected + corrected);
}

TEST(FrontendTracking, DepthsAgreeWithTheRayCastDepthWithinTheNoiseModel) {
  const Sequence& s = walk();
  // Corners on depth edges allowed, so that the patch statistic has edges to refuse.
  FrontendConfig config;
  config.depth_edge_margin_px = 0;
  FeatureTracker tracker(s.camera, config);
  std::vector<double> z_scores;
  std::size_t with_depth = 0, total = 0, edge_features = 0, edge_with_depth = 0;
  const double range_max = s.camera->calibration().depth_max_m, range_min = s.camera->calibration().depth_min_m;
  for (std::size_t k = 0; k < 6; ++k) {
    const FeatureFrame out = tracker.track(s.frames[k]);
    const SE3 T_C_W = s.T_W_C[k].inverse();
    for (const FeatureObservation& o : out.features) {
      ++total;
      // True depths over the 3x3 patch: a relative spread above 0.3 is a silhouette.
      double z_min = 1e9, z_max = 0, z_centre = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector2d px(std::round(o.uv.x()) + dx, std::round(o.uv.y()) + dy);
          const auto p = surface_point(s, s.T_W_C[k], px);
          const double z = p ? (T_C_W * *p).z() : 1e9;
          z_min = std::min(z_min, z);
          z_max = std::max(z_max, z);
          if (dx == 0 && dy == 0) z_centre = z;
        }
      // A silhouette the sensor sees on both sides (a background beyond range leaves only one).
      const bool edge = (z_max - z_min) > 0.3 * z_min && z_max < range_max;
      edge_features += edge;
      if (!o.depth_m) continue;
      ++with_depth;
      EXPECT_GE(*o.depth_m, range_min);
      EXPECT_LE(*o.depth_m, range_max);
      edge_with_depth += edge;
      const double sigma = simulation::depth_sigma(z_centre, s.noise);
      z_scores.push_back(std::abs(*o.depth_m - z_centre) / sigma);
    }
  }
  const double within3 =
      static_cast<double>(std::count_if(z_scores.begin(), z_scores.end(), [](double z) { return z <= 3.0; })) /
      static_cast<double>(z_scores.size());
  std::cout << "[ depth ] " << with_depth << " of " << total << " observations with depth; |error|/sigma median "
            << quantile(z_scores, 0.5) << ", p95 " << quantile(z_scores, 0.95) << ", max " << quantile(z_scores, 1.0)
            << ", within 3 sigma " << within3 << "; silhouette features " << edge_features << " (with depth "
            << edge_with_depth << ")\n";
  ASSERT_GT(z_scores.size(), 150u);  // most corners of this lab lie beyond the 5 m range
  EXPECT_GT(within3, 0.97);
  EXPECT_LT(quantile(z_scores, 1.0), 10.0);  // no foreground / background mix-up
  EXPECT_GT(edge_features, 3u);
  // Edge holes may leave one side only. With the drift check 2 of 18 silhouette features get a
  // depth (1 without), both within 2 sigma of the truth: the bound (1/8, was 1/10) was set after
  // that measurement; a depth mixing the two sides would fail the maximum above.
  EXPECT_LE(edge_with_depth, edge_features / 8);
}

TEST(FrontendTracking, RansacRemovesInjectedOutliers) {
  const Sequence& s = walk();
  // Three frames apart (11 cm): a wider baseline conditions F better than one frame (4 cm).
  constexpr std::size_t kSkip = 3;
  // Control run without corruption.
  FeatureTracker clean(s.camera);
  clean.track(s.frames[0]);
  clean.track(s.frames[kSkip]);
  const std::size_t clean_rejected = clean.stats().rejected_ransac;
  EXPECT_LT(clean_rejected, 10u);

  FeatureTracker tracker(s.camera);
  tracker.track(s.frames[0]);
  // Move ten tracks by 5 px across their epipolar line (the line through the epipole; a shift
  // along it is invisible to any two-view check). Epipole: the previous camera centre seen from
  // the current camera, K t in homogeneous pixels (the camera has no distortion).
  ASSERT_EQ(s.camera->distortion(), DistortionModel::kNone);
  const Vec3 e = s.camera->K() * (s.T_W_C[kSkip].inverse() * s.T_W_C[0].t);
  std::set<std::uint64_t> corrupted;
  tracker.set_track_hook([&](const std::vector<std::uint64_t>& ids, std::vector<Eigen::Vector2d>& uv) {
    for (std::size_t i = 0; i < 10; ++i) {
      const std::size_t j = i * ids.size() / 10;
      const Eigen::Vector2d along = e.head<2>() - e.z() * uv[j];
      uv[j] += 5.0 * Eigen::Vector2d(-along.y(), along.x()).normalized();
      corrupted.insert(ids[j]);
    }
  });
  const FeatureFrame second = tracker.track(s.frames[kSkip]);
  ASSERT_EQ(corrupted.size(), 10u);
  for (const FeatureObservation& o : second.features) EXPECT_EQ(corrupted.count(o.track_id), 0u) << o.track_id;
  EXPECT_GE(tracker.stats().rejected_ransac, 10u);
  EXPECT_LE(tracker.stats().rejected_ransac, clean_rejected + 13);  // the rest is untouched
}

TEST(FrontendTracking, DeterministicAndTrackIdsStable) {
  const Sequence& s = walk();
  FeatureTracker a(s.camera), b(s.camera);
  std::set<std::uint64_t> seen, ended;
  std::uint64_t max_id = 0;
  std::vector<std::uint64_t> previous;
  for (std::size_t k = 0; k < 8; ++k) {
    const FeatureFrame fa = a.track(s.frames[k]);
    const FeatureFrame fb = b.track(s.frames[k]);
    ASSERT_EQ(fa.features.size(), fb.features.size());
    for (std::size_t i = 0; i < fa.features.size(); ++i) {
      EXPECT_EQ(fa.features[i].track_id, fb.features[i].track_id);
      EXPECT_EQ(fa.features[i].uv, fb.features[i].uv);
      EXPECT_EQ(fa.features[i].depth_m, fb.features[i].depth_m);
    }
    EXPECT_EQ(fa.t, s.frames[k].t);
    const FrontendStats& st = a.stats();
    EXPECT_EQ(st.tracked + st.new_features, fa.features.size());
    EXPECT_LE(fa.features.size(), 150u);
    // Detection is batched: only when at least detect_min_missing (10) tracks are missing.
    if (st.tracked > 140) {
      EXPECT_EQ(st.new_features, 0u) << "frame " << k;
    } else {
      EXPECT_GT(st.new_features, 0u) << "frame " << k;
    }
    std::size_t continued = 0, fresh = 0;
    for (std::size_t i = 0; i < fa.features.size(); ++i) {
      const std::uint64_t id = fa.features[i].track_id;
      if (i > 0) {
        EXPECT_GT(id, fa.features[i - 1].track_id);
      }
      EXPECT_EQ(ended.count(id), 0u) << "track " << id << " came back";
      if (seen.count(id)) {
        ++continued;
      } else {
        if (k > 0) {
          EXPECT_GT(id, max_id);  // new corners get new ids
        }
        ++fresh;
      }
    }
    EXPECT_EQ(continued, st.tracked);
    EXPECT_EQ(fresh, st.new_features);
    const std::set<std::uint64_t> now = [&] {
      std::set<std::uint64_t> ids;
      for (const auto& o : fa.features) ids.insert(o.track_id);
      return ids;
    }();
    for (std::uint64_t id : previous)
      if (!now.count(id)) ended.insert(id);
    previous.assign(now.begin(), now.end());
    for (std::uint64_t id : now) {
      seen.insert(id);
      max_id = std::max(max_id, id);
    }
  }
  // RGB input (grey replicated) gives the same features as grey.
  FeatureTracker grey(s.camera), rgb(s.camera);
  for (std::size_t k = 0; k < 2; ++k) {
    RgbdFrame colour = s.frames[k];
    colour.intensity = ImageU8(colour.intensity.width, colour.intensity.height, 3);
    for (std::size_t i = 0; i < s.frames[k].intensity.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) colour.intensity.pixels[3 * i + static_cast<std::size_t>(c)] = s.frames[k].intensity.pixels[i];
    const FeatureFrame from_grey = grey.track(s.frames[k]);
    const FeatureFrame from_rgb = rgb.track(colour);
    ASSERT_EQ(from_grey.features.size(), from_rgb.features.size());
    for (std::size_t i = 0; i < from_grey.features.size(); ++i) EXPECT_EQ(from_grey.features[i].uv, from_rgb.features[i].uv);
  }
  // After a reset everything is new, with ids beyond all earlier ones.
  a.reset();
  const FeatureFrame after = a.track(s.frames[8]);
  EXPECT_EQ(a.stats().tracked, 0u);
  ASSERT_FALSE(after.features.empty());
  EXPECT_GT(after.features.front().track_id, max_id);
}

TEST(FrontendTracking, KltThreadsChangeNothing) {
  // The KLT's points are split over klt_threads workers; each point has its own window, so any
  // split gives the same tracks to the last bit.
  const Sequence& s = walk();
  FrontendConfig one, three;
  one.klt_threads = 1;
  three.klt_threads = 3;
  FeatureTracker a(s.camera, one), b(s.camera, three);
  std::size_t compared = 0;
  for (std::size_t k = 0; k < 8; ++k) {
    const FeatureFrame fa = k > 0 ? a.track(s.frames[k], R_cur_prev(s, k)) : a.track(s.frames[k]);
    const FeatureFrame fb = k > 0 ? b.track(s.frames[k], R_cur_prev(s, k)) : b.track(s.frames[k]);
    ASSERT_EQ(fa.features.size(), fb.features.size()) << "frame " << k;
    for (std::size_t i = 0; i < fa.features.size(); ++i) {
      ASSERT_EQ(fa.features[i].track_id, fb.features[i].track_id);
      ASSERT_EQ(fa.features[i].uv, fb.features[i].uv);
      ASSERT_EQ(fa.features[i].depth_m, fb.features[i].depth_m);
    }
    compared += a.stats().tracked;
  }
  EXPECT_GT(compared, 500u);
}

TEST(FrontendTracking, GyroPredictionKeepsTracksThroughFastRotation) {
  constexpr double kStepDeg = 15.0;  // ~120 px per frame at f = 460 px, beyond KLT's reach
  const Sequence& s = pan(kStepDeg * 3.14159265358979 / 180.0);
  std::size_t tracked[2] = {0, 0}, wrong[2] = {0, 0}, detected = 0;
  for (const bool imu : {false, true}) {
    FeatureTracker tracker(s.camera);
    const FeatureFrame first = tracker.track(s.frames[0]);
    detected = first.features.size();
    const FeatureFrame second = imu ? tracker.track(s.frames[1], R_cur_prev(s, 1)) : tracker.track(s.frames[1]);
    tracked[imu] = tracker.stats().tracked;
    for (const FeatureObservation& o : second.features) {
      const auto it = std::find_if(first.features.begin(), first.features.end(),
                                   [&](const FeatureObservation& f) { return f.track_id == o.track_id; });
      if (it == first.features.end()) continue;
      const auto p = surface_point(s, s.T_W_C[0], it->uv);
      const auto predicted = p ? s.camera->project(s.T_W_C[1].inverse() * *p) : std::nullopt;
      wrong[imu] += !predicted || (o.uv - *predicted).norm() > 2.0;
    }
  }
  std::cout << "[ gyro ] " << kStepDeg << " deg pan: " << detected << " features; without prediction " << tracked[0]
            << " tracked (" << wrong[0] << " > 2 px off), with " << tracked[1] << " (" << wrong[1] << ")\n";
  EXPECT_GT(tracked[1], detected / 2);  // ~ 1/5 leave the field of view
  EXPECT_GT(tracked[1], tracked[0] + detected / 5);
  EXPECT_EQ(wrong[1], 0u);
}

}  // namespace
}  // namespace navaid::estimation
