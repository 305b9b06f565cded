#include "device_fixture.hpp"

#include "navaid/core/semantic_classes.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/sensor_rig.hpp"
#include "navaid/simulation/simulation_config.hpp"

namespace navaid::testing {

DeviceWalk rendered_device_walk(int frames) {
  using C = SemanticClass;
  simulation::World world;
  world.add(simulation::PlanePatch{SE3(Quat::Identity(), Vec3(4, 0, 0)), 12.0, 12.0}, {C::kFloor});
  world.add(simulation::Box{SE3(Quat::Identity(), Vec3(3.0, 0.6, 0.5)), Vec3(0.3, 0.3, 0.5)}, {C::kBench});
  const simulation::RayCaster caster(world);
  DeviceWalk walk;
  walk.camera = simulation::rescale_camera(simulation::sensor_preset("d455").camera, 160, 120);
  // Body: x forward, z up; the camera's optical axis along the body's x.
  Mat3 R_B_C;
  R_B_C.col(0) = -Vec3::UnitY();
  R_B_C.col(1) = -Vec3::UnitZ();
  R_B_C.col(2) = Vec3::UnitX();
  walk.camera.T_B_C = SE3(Quat(R_B_C), Vec3::Zero());
  const auto model = make_camera_model(walk.camera);
  const simulation::RgbdRenderer renderer(caster, *model);
  simulation::RenderOptions options;
  options.max_depth = 6.0;
  for (int k = 0; k < frames; ++k) {
    StateEstimate e;
    e.t = seconds_to_ns(1.0 + 0.1 * k);
    e.T_W_B = SE3(Quat::Identity(), Vec3(0.1 * k, 0.0, 0.8));
    e.v_W = Vec3(1.0, 0.0, 0.0);
    e.covariance = 1e-6 * Mat15::Identity();
    e.mode = EstimatorMode::kRgbdVio;
    simulation::RenderedFrame rendered;
    renderer.render(e.T_W_B * walk.camera.T_B_C, options, rendered);
    RgbdFrame f;
    f.t = e.t;
    f.index = static_cast<std::uint64_t>(k);
    f.camera = walk.camera.name;
    f.depth = rendered.depth;
    f.labels = rendered.labels;
    f.label_confidence = ImageF32(rendered.depth.width, rendered.depth.height, 1, 0.9f);
    f.intensity = rendered.intensity;
    walk.frames.push_back(std::move(f));
    walk.estimates.push_back(e);
  }
  return walk;
}

}  // namespace navaid::testing
