// Cost of the simulator's image noise models on one rendered 640x480 street frame, single thread:
// RGB-D noise (disparity noise, edge holes, dropout, intensity noise), label confusion (cells,
// boundary erosion, confidences) and both together. Budget: both together <= 15 ms per frame
// (the time column, in ms per frame).
#include <benchmark/benchmark.h>

#include "navaid/core/camera.hpp"
#include "navaid/simulation/label_confusion_model.hpp"
#include "navaid/simulation/rgbd_noise_model.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"

namespace {

using namespace navaid;
using namespace navaid::simulation;

// A 60 m street along W x with the thin and small classes the confusion model treats specially:
// road, sidewalks with curbs and tactile strips, facades, poles with signs, trees, people, a car.
World street() {
  World w;
  std::uint32_t seed = 100;
  auto surf = [&](SemanticClass c, double scale) { return Surface{c, ++seed, scale, 0.7}; };
  auto box = [](double x, double y, double z, double hx, double hy, double hz) {
    return Box{SE3(Quat::Identity(), Vec3(x, y, z)), Vec3(hx, hy, hz)};
  };
  w.add(PlanePatch{SE3(), 30.0, 3.5}, surf(SemanticClass::kRoad, 0.3));
  for (double s : {-1.0, 1.0}) {
    w.add(box(0.0, s * 3.6, 0.07, 30.0, 0.1, 0.07), surf(SemanticClass::kCurb, 0.1));
    w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0.0, s * 5.7, 0.14)), 30.0, 2.0}, surf(SemanticClass::kSidewalk, 0.25));
    w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0.0, s * 4.3, 0.141)), 30.0, 0.15}, surf(SemanticClass::kTactilePaving, 0.05));
    for (double x = -27.0; x < 30.0; x += 9.0) w.add(box(x, s * 11.0, 6.0, 4.4, 3.3, 6.0), surf(SemanticClass::kBuilding, 0.4));
    for (double x = -28.0; x < 30.0; x += 6.0) {
      w.add(VerticalCylinder{Vec3(x, s * 4.0, 0.14), 0.06, 3.2}, surf(SemanticClass::kPole, 0.05));
      w.add(box(x, s * 4.0, 2.8, 0.02, 0.3, 0.3), surf(SemanticClass::kTrafficSign, 0.05));
      w.add(VerticalCylinder{Vec3(x + 3.0, s * 7.0, 0.14), 0.15, 2.5}, surf(SemanticClass::kTreeTrunk, 0.08));
      w.add(Ellipsoid{SE3(Quat::Identity(), Vec3(x + 3.0, s * 7.0, 3.8)), Vec3(1.6, 1.5, 1.3)},
            surf(SemanticClass::kVegetation, 0.15));
    }
    w.add(VerticalCylinder{Vec3(6.0, s * 5.5, 0.14), 0.25, 1.75}, surf(SemanticClass::kPerson, 0.1));
  }
  w.add(box(12.0, -2.2, 0.75, 2.2, 0.9, 0.75), surf(SemanticClass::kCar, 0.2));
  return w;
}

// Rendered once; the benchmarks time the noise models only.
const RenderedFrame& clean_frame() {
  static const RenderedFrame frame = [] {
    CameraCalibration c;
    c.width = 640;
    c.height = 480;
    c.fx = c.fy = 512.0;
    c.cx = 319.5;
    c.cy = 239.5;
    const auto camera = make_camera_model(c);
    // On the sidewalk at eye height, looking down the street and slightly down (C: x right, y down).
    const Mat3 R_W_C = (Mat3() << 0, -0.1, 0.995, -1, 0, 0, 0, -0.995, -0.1).finished();
    RenderOptions options;
    options.max_depth = 12.0;
    return render(street(), *camera, SE3(Quat(R_W_C).normalized(), Vec3(-20.0, -5.5, 1.6)), options);
  }();
  return frame;
}

RgbdNoiseConfig noise_config() {
  RgbdNoiseConfig c;
  c.focal_px = 512.0;
  c.max_depth_m = 12.0;
  c.disparity_quantization_px = 0.125;
  c.dropout_probability = 0.01;
  c.intensity_shot_gain = 0.2;
  return c;
}

void BM_RgbdNoise(benchmark::State& state) {
  const RenderedFrame& clean = clean_frame();
  const RgbdNoiseConfig config = noise_config();
  NoisyRgbd out;
  std::uint64_t frame = 0;
  for (auto _ : state) {
    apply_rgbd_noise(clean, config, 1, frame++, out);
    benchmark::DoNotOptimize(out.depth.pixels.data());
  }
}
BENCHMARK(BM_RgbdNoise)->Unit(benchmark::kMillisecond);

void BM_LabelConfusion(benchmark::State& state) {
  const RenderedFrame& clean = clean_frame();
  const LabelConfusionModel model;
  LabelPrediction out;
  std::uint64_t frame = 0;
  for (auto _ : state) {
    model.apply(clean.labels, 1, frame++, out);
    benchmark::DoNotOptimize(out.labels.pixels.data());
  }
}
BENCHMARK(BM_LabelConfusion)->Unit(benchmark::kMillisecond);

void BM_SensorNoiseFrame(benchmark::State& state) {
  const RenderedFrame& clean = clean_frame();
  const RgbdNoiseConfig config = noise_config();
  const LabelConfusionModel model;
  NoisyRgbd rgbd;
  LabelPrediction labels;
  std::uint64_t frame = 0;
  for (auto _ : state) {
    apply_rgbd_noise(clean, config, 1, frame, rgbd);
    model.apply(clean.labels, 1, frame++, labels);
    benchmark::DoNotOptimize(rgbd.depth.pixels.data());
    benchmark::DoNotOptimize(labels.labels.pixels.data());
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  // What the models did to the last frame: depth pixels lost (holes, dropout, range) and the
  // realized label accuracy (confusion plus boundary erosion).
  double valid_clean = 0, valid_noisy = 0, labelled = 0, correct = 0;
  for (std::size_t i = 0; i < clean.depth.pixels.size(); ++i) {
    valid_clean += clean.depth.pixels[i] > 0.0f;
    valid_noisy += rgbd.depth.pixels[i] > 0.0f;
    labelled += clean.labels.pixels[i] != 0;
    correct += clean.labels.pixels[i] != 0 && labels.labels.pixels[i] == clean.labels.pixels[i];
  }
  state.counters["depth_lost"] = 1.0 - valid_noisy / valid_clean;
  state.counters["label_accuracy"] = correct / labelled;
}
BENCHMARK(BM_SensorNoiseFrame)->Unit(benchmark::kMillisecond);

}  // namespace
