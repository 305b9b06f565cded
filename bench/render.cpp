// Frames per second of the noise-free RGB-D renderer (depth + labels + intensity) on a street-like
// world of a few hundred primitives, single thread. Budgets: >= 30 fps at 320x240 and >= 10 fps
// at 640x480 (the "fps" counter).
#include <benchmark/benchmark.h>

#include <random>

#include "navaid/core/camera.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"

namespace {

using namespace navaid;
using namespace navaid::simulation;

// A 200 m street along W x: road, sidewalks with curbs, building boxes on both sides, poles,
// trees (trunk cylinder + crown ellipsoid), benches, parked cars, a crosswalk.
World street() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  World w;
  std::uint32_t seed = 0;
  auto surf = [&](SemanticClass c, double scale) { return Surface{c, ++seed, scale, 0.4 + 0.5 * u(rng)}; };
  const double half_len = 100.0;
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, 0, 0)), half_len, 4.0}, surf(SemanticClass::kRoad, 0.3));
  for (double side : {-1.0, 1.0}) {
    w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, side * 6.5, 0.15)), half_len, 2.5}, surf(SemanticClass::kSidewalk, 0.25));
    w.add(ExtrudedPolygon{{{-half_len, side * 4.0}, {half_len, side * 4.0}, {half_len, side * 3.85}, {-half_len, side * 3.85}},
                          0.0, 0.15},
          surf(SemanticClass::kCurb, 0.1));
    w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0, side * 7.2, 0.151)), half_len, 0.15}, surf(SemanticClass::kTactilePaving, 0.05));
    for (double x = -half_len; x < half_len; x += 10.0) {  // 20 buildings per side
      const double depth = 6.0 + 4.0 * u(rng), height = 8.0 + 14.0 * u(rng);
      w.add(Box{SE3(Quat::Identity(), Vec3(x + 5.0, side * (9.0 + 0.5 * depth), 0.5 * height)), Vec3(4.9, 0.5 * depth, 0.5 * height)},
            surf(SemanticClass::kBuilding, 0.4));
    }
    for (double x = -half_len + 2.0; x < half_len; x += 5.0) {  // 40 poles per side, some with signs
      w.add(VerticalCylinder{Vec3(x, side * 4.4, 0.15), 0.06, 3.5 + u(rng)}, surf(SemanticClass::kPole, 0.05));
      if (u(rng) < 0.3)
        w.add(Box{SE3(Quat::Identity(), Vec3(x, side * 4.4, 3.0)), Vec3(0.02, 0.3, 0.3)}, surf(SemanticClass::kTrafficSign, 0.05));
    }
    for (double x = -half_len + 4.5; x < half_len; x += 8.0) {  // 25 trees per side
      const double h = 2.0 + u(rng);
      w.add(VerticalCylinder{Vec3(x, side * 5.0, 0.15), 0.15, h + 0.5}, surf(SemanticClass::kTreeTrunk, 0.08));
      w.add(Ellipsoid{SE3(quat_from_rpy(0, 0, u(rng)), Vec3(x, side * 5.0, 0.15 + h + 1.5)), Vec3(1.8, 1.6, 1.5)},
            surf(SemanticClass::kVegetation, 0.15));
    }
    for (double x = -half_len + 7.0; x < half_len; x += 25.0) {  // benches and parked cars
      w.add(Box{SE3(Quat::Identity(), Vec3(x, side * 7.8, 0.6)), Vec3(0.9, 0.25, 0.45)}, surf(SemanticClass::kBench, 0.1));
      w.add(Box{SE3(quat_from_rpy(0, 0, 0.05 * (u(rng) - 0.5)), Vec3(x + 10.0, side * 2.8, 0.75)), Vec3(2.2, 0.9, 0.75)},
            surf(SemanticClass::kCar, 0.2));
    }
  }
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(20.0, 0, 0.01)), 2.0, 4.0}, surf(SemanticClass::kCrosswalk, 0.5));
  return w;
}

CameraCalibration calibration(int width, int height) {
  CameraCalibration c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.8 * width;  // ~64 deg horizontal field of view
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  c.distortion = DistortionModel::kRadialTangential;
  c.distortion_coeffs = {-0.05, 0.01, 0.0, 0.0};
  return c;
}

void BM_RenderStreet(benchmark::State& state) {
  const RayCaster caster(street());
  const auto cam = make_camera_model(calibration(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))));
  const RgbdRenderer renderer(caster, *cam);
  // Walking along the sidewalk at eye height, looking down the street slightly downwards.
  const Mat3 R_W_C = (Mat3() << 0, -0.1, 0.995, -1, 0, 0, 0, -0.995, -0.1).finished();  // columns x, y, z of C
  RenderOptions options;
  RenderedFrame frame;
  double x = -60.0;
  for (auto _ : state) {
    renderer.render(SE3(Eigen::Quaterniond(R_W_C).normalized(), Vec3(x, -6.5, 1.6)), options, frame);
    benchmark::DoNotOptimize(frame.intensity.pixels.data());
    x += 0.1;
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["primitives"] = static_cast<double>(caster.world().size());
  state.counters["triangles"] = static_cast<double>(caster.mesh().triangles.size());
}
BENCHMARK(BM_RenderStreet)->Args({320, 240})->Args({640, 480})->Unit(benchmark::kMillisecond);

}  // namespace
