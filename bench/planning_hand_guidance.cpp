// The hand-guidance detector on the Structure Core's 640 x 480 grey image: ViSP's AprilTag
// (tag36h11) on a drawn tag 1 m away, on an empty image, and with quad decimation 2; and one
// HandGuidance update (case I, depth patch stats included). One thread.
#include <benchmark/benchmark.h>

#include <random>

#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/hand_guidance.hpp"
#include "navaid/simulation/apriltag_image.hpp"
#include "navaid/simulation/sensor_rig.hpp"

namespace {

using namespace navaid;
using namespace navaid::planning;

std::unique_ptr<CameraModel> camera() { return make_camera_model(simulation::sensor_preset("structure-core").camera); }

/// Textured background (uniform noise blurred over 4 px blocks) with one tag 1 m ahead.
ImageU8 scene(const CameraModel& cam, bool with_tag, ImageF32* depth = nullptr) {
  ImageU8 img(cam.width(), cam.height(), 1, 0);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> value(60, 200);
  for (int v = 0; v < img.height; v += 4) {
    for (int u = 0; u < img.width; u += 4) {
      const auto g = static_cast<std::uint8_t>(value(rng));
      for (int y = v; y < std::min(v + 4, img.height); ++y) {
        for (int x = u; x < std::min(u + 4, img.width); ++x) img.at(x, y) = g;
      }
    }
  }
  if (with_tag) {
    const SE3 T_C_tag(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())), Vec3(0.1, -0.05, 1.0));
    simulation::draw_apriltag(img, cam, T_C_tag, 0.1, simulation::apriltag_cells("36h11", 11), 8, 4, depth);
  }
  return img;
}

void run_detector(benchmark::State& state, bool with_tag, double decimate) {
  const auto cam = camera();
  const ImageU8 img = scene(*cam, with_tag);
  AprilTagDetectorConfig config;
  config.quad_decimate = decimate;
  AprilTagDetector detector(config);
  std::size_t found = 0;
  for (auto _ : state) {
    const auto tags = detector.detect(img);
    found = tags.size();
    benchmark::DoNotOptimize(found);
  }
  state.counters["tags"] = static_cast<double>(found);
}

void BM_AprilTag640x480_Tag(benchmark::State& state) { run_detector(state, true, 1.0); }
void BM_AprilTag640x480_NoTag(benchmark::State& state) { run_detector(state, false, 1.0); }
void BM_AprilTag640x480_Tag_Decimate2(benchmark::State& state) { run_detector(state, true, 2.0); }

void BM_HandGuidanceUpdateCaseI(benchmark::State& state) {
  const auto cam = camera();
  ImageF32 depth(cam->width(), cam->height(), 1, 0.0f);
  const ImageU8 img = scene(*cam, true, &depth);
  AprilTagDetector detector;
  const auto tag = find_tag(detector.detect(img), 11);
  if (!tag) {
    state.SkipWithError("tag not found");
    return;
  }
  HandGuidance guidance({}, *cam, SE3());
  StateEstimate e;
  e.mode = EstimatorMode::kRgbdVio;
  e.covariance = Mat15::Identity() * 1e-6;
  for (auto _ : state) {
    TargetDetection d;
    d.centre_px = tag->centre_px;
    d.depth = depth_patch_stats(depth, d.centre_px, 5, 0.3, 5.0);
    benchmark::DoNotOptimize(guidance.update(e, d));
  }
}

BENCHMARK(BM_AprilTag640x480_Tag)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AprilTag640x480_NoTag)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AprilTag640x480_Tag_Decimate2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HandGuidanceUpdateCaseI)->Unit(benchmark::kMicrosecond);

}  // namespace
