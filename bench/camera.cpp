// Cost of the camera models in the tracker's inner loops: project with its Jacobian (every
// landmark of every frame in the optimizer) and unproject (every new feature).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "navaid/core/camera.hpp"

namespace {

using navaid::CameraCalibration;
using navaid::DistortionModel;

CameraCalibration calibration(DistortionModel model) {
  CameraCalibration c;
  c.distortion = model;
  switch (model) {
    case DistortionModel::kNone:
      c.width = 640, c.height = 480, c.fx = 525.0, c.fy = 524.5, c.cx = 319.5, c.cy = 239.5;
      break;
    case DistortionModel::kRadialTangential:  // EuRoC cam0
      c.width = 752, c.height = 480, c.fx = 458.654, c.fy = 457.296, c.cx = 367.215, c.cy = 248.375;
      c.distortion_coeffs = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
      break;
    case DistortionModel::kEquidistant:
      c.width = 848, c.height = 800, c.fx = 286.1, c.fy = 286.3, c.cx = 421.6, c.cy = 399.5;
      c.distortion_coeffs = {-0.0140, 0.0209, -0.0164, 0.0047};
      break;
  }
  return c;
}

// Pixels spread over the image that the model can unproject, and 3D points behind them.
struct Samples {
  std::vector<Eigen::Vector2d> pixels;
  std::vector<navaid::Vec3> points;
};

Samples samples(const navaid::CameraModel& cam) {
  Samples s;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, cam.width() - 1.0), v(0.0, cam.height() - 1.0);
  std::uniform_real_distribution<double> depth(0.5, 20.0);
  while (s.pixels.size() < 1024) {
    const double y = v(rng);  // y before x: the order of record (random_draws.hpp)
    const Eigen::Vector2d px(u(rng), y);
    const auto bearing = cam.unproject(px);
    if (!bearing) continue;
    s.pixels.push_back(px);
    s.points.push_back(depth(rng) * *bearing);
  }
  return s;
}

void BM_ProjectWithJacobian(benchmark::State& state, DistortionModel model) {
  const auto cam = navaid::make_camera_model(calibration(model));
  const Samples s = samples(*cam);
  Eigen::Matrix<double, 2, 3> J;
  std::size_t i = 0;
  for (auto _ : state) {
    auto px = cam->project(s.points[i++ & 1023], &J);
    benchmark::DoNotOptimize(px);
    benchmark::DoNotOptimize(J);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Unproject(benchmark::State& state, DistortionModel model) {
  const auto cam = navaid::make_camera_model(calibration(model));
  const Samples s = samples(*cam);
  std::size_t i = 0;
  for (auto _ : state) {
    auto bearing = cam->unproject(s.pixels[i++ & 1023]);
    benchmark::DoNotOptimize(bearing);
  }
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK_CAPTURE(BM_ProjectWithJacobian, pinhole, DistortionModel::kNone);
BENCHMARK_CAPTURE(BM_ProjectWithJacobian, radtan, DistortionModel::kRadialTangential);
BENCHMARK_CAPTURE(BM_ProjectWithJacobian, equidistant, DistortionModel::kEquidistant);
BENCHMARK_CAPTURE(BM_Unproject, pinhole, DistortionModel::kNone);
BENCHMARK_CAPTURE(BM_Unproject, radtan, DistortionModel::kRadialTangential);
BENCHMARK_CAPTURE(BM_Unproject, equidistant, DistortionModel::kEquidistant);
