// Frames per second of the noise-free RGB-D renderer (depth + labels + intensity) in the `route1`
// scenario, walked with the head mount (D455-like camera, rescaled for 320x240), moving people
// included, single thread. Budgets (issue 3): >= 30 fps at 320x240 and >= 10 fps at 640x480
// (the "fps" counter).
#include <benchmark/benchmark.h>

#include "navaid/core/camera.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/sensor_rig.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace {

using namespace navaid;
using namespace navaid::simulation;

void BM_RenderRoute1(benchmark::State& state) {
  const Scenario scenario = make_scenario("route1");
  const RayCaster caster(scenario.world);
  const Mount mount = mount_preset("head");
  const WalkerTrajectory walker(scenario.path, mount.apply(WalkerConfig{}));
  const CameraCalibration calib = rescale_camera(sensor_preset("d455").camera, static_cast<int>(state.range(0)),
                                                 static_cast<int>(state.range(1)));
  const auto camera = make_camera_model(calib);
  const RgbdRenderer renderer(caster, *camera);
  RenderOptions options;
  options.max_depth = 7.2;  // as the simulator renders the D455 (1.2 x its 6 m range)
  RenderedFrame frame;
  double t = 0.0;
  for (auto _ : state) {
    // Walk along the whole route so that every part of the street is measured.
    const SE3 T_W_C = walker.state(t).T_W_B * mount.T_B_C();
    const RayCaster people(moving_world(scenario.moving, t));
    renderer.render(T_W_C, options, frame, &people);
    benchmark::DoNotOptimize(frame.intensity.pixels.data());
    t += 1.0;
    if (t > walker.duration()) t = 0.0;
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["primitives"] = static_cast<double>(caster.world().size());
  state.counters["triangles"] = static_cast<double>(caster.mesh().triangles.size());
}
BENCHMARK(BM_RenderRoute1)->Args({320, 240})->Args({640, 480})->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace
