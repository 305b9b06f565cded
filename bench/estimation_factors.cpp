// Cost of the estimator's inner loops: preintegrating the IMU samples between two keyframes
// (200 samples = 1 s at 200 Hz; once per keyframe, again on repropagation) and evaluating each
// factor with all Jacobians (every factor, every solver iteration), the visual ones also with the
// camera-IMU time offset.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "navaid/core/random_draws.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/gps_position_factor.hpp"
#include "navaid/estimation/factors/imu_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/magnetometer_yaw_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/factors/time_offset_factors.hpp"
#include "navaid/estimation/imu_preintegration.hpp"

namespace {

using namespace navaid;
using namespace navaid::estimation;

ImuNoise noise() {
  ImuNoise n;
  n.gyro_noise_density = 1.6968e-4;
  n.gyro_random_walk = 1.9393e-5;
  n.accel_noise_density = 2.0e-3;
  n.accel_random_walk = 3.0e-3;
  return n;
}

std::vector<ImuSample> samples(int count) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 0.3);
  std::vector<ImuSample> s(count);
  for (int k = 0; k < count; ++k) {
    s[k].t = Timestamp{k} * 5'000'000;
    s[k].gyro = draw_vector<3>([&] { return n(rng); });
    s[k].accel = draw_vector<3>([&] { return n(rng); });
    s[k].accel.z() += 9.81;
  }
  return s;
}

void BM_Preintegrate200(benchmark::State& state) {
  const std::vector<ImuSample> s = samples(201);  // 200 intervals
  for (auto _ : state) {
    ImuPreintegration p(noise(), Vec3::Zero(), Vec3::Zero());
    for (const ImuSample& x : s) p.add(x);
    benchmark::DoNotOptimize(p.covariance().data());
  }
  state.SetItemsProcessed(state.iterations() * 200);
}
BENCHMARK(BM_Preintegrate200);

struct Blocks {
  double pose_a[kPoseSize], pose_b[kPoseSize], extrinsic[kPoseSize];
  double sb_a[kSpeedBiasSize] = {0.5, 0.1, 0.0, 1e-3, 0, 0, 0.01, 0, 0};
  double sb_b[kSpeedBiasSize] = {0.6, 0.1, 0.0, 1e-3, 0, 0, 0.01, 0, 0};
  double lambda[1] = {0.3};
  double td[1] = {0.004};
  double align[4] = {0.4, 1.0, 2.0, 0.0};
  Blocks() {
    pose_to_block(SE3(quat_from_rpy(0.1, 0.05, 0.3), Vec3(1, 2, 1.7)), pose_a);
    pose_to_block(SE3(quat_from_rpy(0.12, 0.02, 0.35), Vec3(1.5, 2.1, 1.7)), pose_b);
    pose_to_block(SE3(quat_from_rpy(-1.57, 0.0, -1.57), Vec3(0.05, 0.0, 0.02)), extrinsic);
  }
};

template <int kResiduals>
void evaluate(benchmark::State& state, const ceres::CostFunction& f, std::vector<double*> blocks) {
  std::vector<std::vector<double>> J;
  std::vector<double*> J_ptrs;
  for (int size : f.parameter_block_sizes()) J.emplace_back(static_cast<std::size_t>(size * kResiduals));
  for (auto& j : J) J_ptrs.push_back(j.data());
  double r[kResiduals];
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.Evaluate(blocks.data(), r, J_ptrs.data()));
    benchmark::ClobberMemory();
  }
}

void BM_ImuFactor(benchmark::State& state) {
  Blocks b;
  ImuPreintegration p(noise(), Vec3::Zero(), Vec3::Zero());
  for (const ImuSample& x : samples(201)) p.add(x);
  const ImuFactor f(p);
  evaluate<15>(state, f, {b.pose_a, b.sb_a, b.pose_b, b.sb_b});
}
BENCHMARK(BM_ImuFactor);

void BM_ReprojectionFactor(benchmark::State& state) {
  Blocks b;
  const ReprojectionFactor f({0.1, -0.05}, {0.12, -0.04}, 525.0, 1.5);
  evaluate<2>(state, f, {b.pose_a, b.pose_b, b.extrinsic, b.lambda});
}
BENCHMARK(BM_ReprojectionFactor);

void BM_InverseDepthFactor(benchmark::State& state) {
  Blocks b;
  const InverseDepthFactor f(3.2, inverse_depth_sigma(0.2, 525.0, 0.075));
  evaluate<1>(state, f, {b.lambda});
}
BENCHMARK(BM_InverseDepthFactor);

void BM_Depth3dFactor(benchmark::State& state) {
  Blocks b;
  const Depth3dFactor f({0.1, -0.05}, {0.12, -0.04}, 3.1, 525.0, inverse_depth_sigma(0.2, 525.0, 0.075));
  evaluate<3>(state, f, {b.pose_a, b.pose_b, b.extrinsic, b.lambda});
}
BENCHMARK(BM_Depth3dFactor);

// The same features with the time offset: the plain factor plus moving two measurements.
const TimedObservation kAnchor{{0.1, -0.05}, {0.4, 0.1}, 0.0};
const TimedObservation kTarget{{0.12, -0.04}, {0.35, 0.12}, 0.002};

void BM_ReprojectionTdFactor(benchmark::State& state) {
  Blocks b;
  const ReprojectionTdFactor f(kAnchor, kTarget, 525.0, 1.5);
  evaluate<2>(state, f, {b.pose_a, b.pose_b, b.extrinsic, b.lambda, b.td});
}
BENCHMARK(BM_ReprojectionTdFactor);

void BM_Depth3dTdFactor(benchmark::State& state) {
  Blocks b;
  const Depth3dTdFactor f(kAnchor, kTarget, 3.1, -0.4, 525.0, inverse_depth_sigma(0.2, 525.0, 0.075));
  evaluate<3>(state, f, {b.pose_a, b.pose_b, b.extrinsic, b.lambda, b.td});
}
BENCHMARK(BM_Depth3dTdFactor);

void BM_GpsPositionFactor(benchmark::State& state) {
  Blocks b;
  const GpsPositionFactor f(Vec3(1, 4, 2), Vec3(9, 9, 25).asDiagonal(), Vec3(0, 0, 0.3));
  evaluate<3>(state, f, {b.pose_a, b.align});
}
BENCHMARK(BM_GpsPositionFactor);

void BM_MagnetometerYawFactor(benchmark::State& state) {
  Blocks b;
  const MagnetometerYawFactor f(Vec3(18e-6, 5e-6, -45e-6), Vec3(0, 20e-6, -45e-6), 0.05);
  evaluate<1>(state, f, {b.pose_a, b.align});
}
BENCHMARK(BM_MagnetometerYawFactor);

}  // namespace
