#include "navaid/simulation/sensor_streams.hpp"

#include <vector>

#include "navaid/io/image_io.hpp"
#include "navaid/simulation/frame_rng.hpp"

namespace navaid::simulation {

std::uint64_t model_seed(std::uint64_t seed, ModelStream s) { return mix64(mix64(seed) ^ static_cast<std::uint64_t>(s)); }

ImuModelOptions imu_options(const SimulationConfig& config) {
  ImuModelOptions o = config.imu_options;
  o.seed = model_seed(config.seed, ModelStream::kImu);
  return o;
}

std::optional<RayCaster> moving_caster(const Scenario& scenario, double t_s, const Vec3& near_W) {
  std::vector<MovingObject> nearby;
  for (const auto& m : scenario.moving)
    if ((moving_position(m, t_s) - near_W.head<2>()).norm() < kMovingObjectRadiusM) nearby.push_back(m);
  if (nearby.empty()) return std::nullopt;
  return RayCaster(moving_world(nearby, t_s));
}

Timestamp camera_stamp(const SimulationConfig& c, Timestamp t) {
  return kSimulationEpoch + t - seconds_to_ns(c.camera_time_offset_s);
}

ImageF32 quantize_depth(const ImageF32& depth, double unit_m) {
  const ImageU16 raw = io::depth_to_png_units(depth, unit_m, "<rendered depth>");
  ImageF32 out(raw.width, raw.height, 1);
  for (std::size_t i = 0; i < raw.pixels.size(); ++i) out.pixels[i] = static_cast<float>(raw.pixels[i] * unit_m);
  return out;
}

}  // namespace navaid::simulation
