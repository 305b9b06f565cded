#pragma once
// What the batch simulator (simulator.hpp) and the closed-loop sensors (online_sensors.hpp) share,
// so that a frame rendered online is the frame `navaid simulate` would write from the same pose:
// the per-model noise seeds, the moving objects near the camera, the camera clock, depth quantized
// as the depth PNGs store it.
#include <cstdint>
#include <optional>

#include "navaid/core/image.hpp"
#include "navaid/core/time.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"

namespace navaid::simulation {

/// Independent random engines per sensor model, all derived from the one noise seed.
enum class ModelStream : std::uint64_t { kImu = 101, kGps = 102, kMag = 103, kFeatures = 104, kBiases = 105 };
std::uint64_t model_seed(std::uint64_t seed, ModelStream stream);

/// The IMU model's options with its seed drawn from the configuration's noise seed.
ImuModelOptions imu_options(const SimulationConfig& config);

/// Moving objects farther than this from the camera cannot appear in its depth range or block a
/// nearby landmark; leaving them out keeps the per-frame BVH tiny.
constexpr double kMovingObjectRadiusM = 40.0;

/// The scenario's people and vehicles within kMovingObjectRadiusM of near_W at time t, ready for
/// ray casting; none when there are none.
std::optional<RayCaster> moving_caster(const Scenario& scenario, double t_s, const Vec3& near_W);

/// Camera frames carry the camera clock: taken at trajectory time t (IMU clock), stamped t - offset,
/// from kSimulationEpoch.
Timestamp camera_stamp(const SimulationConfig& config, Timestamp t);

/// Depth through the integer units of a depth PNG (unit_m per step), so that a depth rendered now
/// equals the one a recording or the render cache stores.
ImageF32 quantize_depth(const ImageF32& depth, double unit_m);

}  // namespace navaid::simulation
