// Cost of the image front end per frame at 640x480 with up to 150 features, on rendered lab-walk-1
// frames (hand mount, Structure Core camera, default RGB-D noise, 30 Hz). One iteration tracks
// the next frame; after the last frame the tracker restarts (outside the timing). Counters: the
// median, mean and 95th percentile of the tracker's own per-frame total, the median of each stage,
// the fraction of frames that run detection and their median total.
// Modes: 0 no gyro prediction, 1 with it, 2 without the depth-edge margin, 3 as 1 with the KLT
// on one thread (frontend.klt_threads = 1; the default splits its points over 2). OpenCV's own
// parallelism is off: cv::setNumThreads(1) here, because the front end itself sets nothing global.
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <memory>
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


namespace {

using namespace navaid;

struct Frames {
  std::shared_ptr<const CameraModel> camera;
  std::vector<RgbdFrame> frames;
  std::vector<Eigen::Matrix3d> R_cur_prev;  // true camera rotation from the previous frame
};

const Frames& frames() {
  static const Frames f = [] {
    constexpr int kCount = 90;  // 3 s of walking
    constexpr double kRate = 30.0;
    simulation::ScenarioOptions so;
    so.people = so.vehicles = false;
    const simulation::Scenario scenario = simulation::make_scenario("lab-walk-1", so);
    const simulation::Mount mount = simulation::mount_preset("hand");
    simulation::WalkerConfig walker = mount.apply(simulation::WalkerConfig{});
    walker.ground_z_m = scenario.ground_z_m;
    const simulation::WalkerTrajectory trajectory(scenario.path, walker);
    const CameraCalibration calib =
        simulation::rescale_camera(simulation::sensor_preset("structure-core").camera, 640, 480);
    Frames out;
    out.camera = make_camera_model(calib);
    const simulation::RayCaster caster(scenario.world);
    const simulation::RgbdRenderer renderer(caster, *out.camera);
    const simulation::RgbdNoiseConfig noise = simulation::rgbd_noise_config(calib);
    simulation::RenderOptions options;
    options.render_labels = false;
    SE3 previous;
    for (int k = 0; k < kCount; ++k) {
      const SE3 T_W_C = trajectory.state(4.0 + k / kRate).T_W_B * mount.T_B_C();
      simulation::NoisyRgbd noisy = simulation::apply_rgbd_noise(renderer.render(T_W_C, options), noise, 5,
                                                                 static_cast<std::uint64_t>(k));
      RgbdFrame frame;
      frame.t = static_cast<Timestamp>(k * 1e9 / kRate);
      frame.index = static_cast<std::uint64_t>(k);
      frame.intensity = std::move(noisy.intensity);
      frame.depth = std::move(noisy.depth);
      out.frames.push_back(std::move(frame));
      out.R_cur_prev.push_back((T_W_C.q.conjugate() * previous.q).toRotationMatrix());
      previous = T_W_C;
    }
    return out;
  }();
  return f;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

void BM_FrontendTrack(benchmark::State& state) {
  cv::setNumThreads(1);
  const bool gyro = state.range(0) == 1 || state.range(0) == 3;
  const Frames& f = frames();
  estimation::FrontendConfig config;
  if (state.range(0) == 2) config.depth_edge_margin_px = 0;
  if (state.range(0) == 3) config.klt_threads = 1;
  estimation::FeatureTracker tracker(f.camera, config);
  std::size_t k = 0;
  std::vector<double> total, pyramid, klt, ransac, detect, depth, features, with_detection;
  for (auto _ : state) {
    if (k == f.frames.size()) {
      state.PauseTiming();
      tracker.reset();
      k = 0;
      state.ResumeTiming();
    }
    const FeatureFrame out = gyro && k > 0 ? tracker.track(f.frames[k], f.R_cur_prev[k]) : tracker.track(f.frames[k]);
    benchmark::DoNotOptimize(out.features.data());
    const estimation::FrontendStats& s = tracker.stats();
    if (k > 0) {  // the first frame only detects
      total.push_back(s.ms_total);
      pyramid.push_back(s.ms_pyramid);
      klt.push_back(s.ms_klt);
      ransac.push_back(s.ms_ransac);
      detect.push_back(s.ms_detect);
      depth.push_back(s.ms_depth);
      features.push_back(static_cast<double>(out.features.size()));
      if (s.new_features > 0) with_detection.push_back(s.ms_total);
    }
    ++k;
  }
  state.counters["median_ms"] = percentile(total, 0.5);
  state.counters["p95_ms"] = percentile(total, 0.95);
  double sum = 0;
  for (double t : total) sum += t;
  state.counters["mean_ms"] = total.empty() ? 0.0 : sum / static_cast<double>(total.size());
  // Detection is batched (detect_min_missing): frames that detect cost more.
  state.counters["detect_frames"] = static_cast<double>(with_detection.size()) / static_cast<double>(std::max<std::size_t>(1, total.size()));
  state.counters["detect_frame_median_ms"] = percentile(with_detection, 0.5);
  state.counters["pyramid_ms"] = percentile(pyramid, 0.5);
  state.counters["klt_fb_ms"] = percentile(klt, 0.5);
  state.counters["border_ransac_ms"] = percentile(ransac, 0.5);
  state.counters["detect_ms"] = percentile(detect, 0.5);
  state.counters["depth_ms"] = percentile(depth, 0.5);
  state.counters["features"] = percentile(features, 0.5);
}
BENCHMARK(BM_FrontendTrack)->ArgName("mode")->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace
