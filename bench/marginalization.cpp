// Cost of one window shift's marginalization: the oldest of 10 keyframes (pose, speed-bias and the
// inverse depths of the features anchored in it) is Schur-complemented out of its IMU factor, the
// previous prior and its features' reprojection / inverse-depth / 3D depth factors; and the cost of
// evaluating the resulting prior factor (once per solver iteration).
//
// Window: 10 keyframes 0.3 s apart on a simulated walk (noisy 200 Hz IMU), 150 features each seen
// in 3 to 10 consecutive keyframes (60 of them anchored in the oldest keyframe, as long tracks
// are), a dense previous prior on every pose and the two oldest speed-biases.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <memory>
#include <random>
#include <vector>

#include <ceres/loss_function.h>

#include "navaid/core/random_draws.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/imu_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/marginalization.hpp"
#include "navaid/simulation/imu_model.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace {

using namespace navaid;
using namespace navaid::estimation;

constexpr int kKeyframes = 10;
constexpr int kFeatures = 150;
constexpr int kAnchoredInOldest = 60;
constexpr double kFocal = 460.0;
constexpr double kSigmaPx = 1.5;

struct Window {
  std::array<std::array<double, kPoseSize>, kKeyframes> pose{};
  std::array<std::array<double, kSpeedBiasSize>, kKeyframes> speed_bias{};
  std::array<double, kPoseSize> extrinsic{};
  std::array<double, kFeatures> lambda{};
  std::vector<MarginalizationTerm> oldest_terms;  // every factor touching keyframe 0's states
  std::size_t factors = 0;                        // in the whole window
};

// The previous marginalization's prior: dense, full rank, on the given blocks.
std::shared_ptr<MarginalizationPrior> previous_prior(const std::vector<double*>& blocks,
                                                     const std::vector<BlockKind>& kinds, std::mt19937_64& rng) {
  auto prior = std::make_shared<MarginalizationPrior>();
  std::normal_distribution<double> normal(0.0, 1.0);
  int columns = 0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const int ambient = kinds[i] == BlockKind::kPose ? kPoseSize : kSpeedBiasSize;
    prior->blocks.push_back(blocks[i]);
    prior->kinds.push_back(kinds[i]);
    prior->ambient_sizes.push_back(ambient);
    prior->tangent_offsets.push_back(columns);
    prior->x0.emplace_back(blocks[i], blocks[i] + ambient);
    columns += tangent_size(kinds[i], ambient);
  }
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(columns, columns, [&]() { return normal(rng); });
  prior->J = 30.0 * Eigen::MatrixXd::Identity(columns, columns) + A;
  prior->r = Eigen::VectorXd::NullaryExpr(columns, [&]() { return normal(rng); });
  return prior;
}

// Fills w in place: the factors hold the addresses of its blocks.
void make_window(Window& w) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto noise3 = [&](double sigma) -> Vec3 { return draw_vector<3>([&] { return normal(rng); }) * sigma; };
  ImuCalibration calibration;
  calibration.rate_hz = 200.0;
  calibration.gyro_noise_density = 1.6968e-4;
  calibration.gyro_random_walk = 1.9393e-5;
  calibration.accel_noise_density = 2.0e-3;
  calibration.accel_random_walk = 3.0e-3;
  const simulation::WalkerTrajectory walk({{0.0, 0.0}, {10.0, 0.0}, {10.0, 8.0}});
  simulation::ImuModelOptions imu_options;
  imu_options.seed = 7;
  simulation::ImuModel imu(calibration, imu_options);
  const double t0 = 2.0, spacing = 0.3;
  const auto stream = simulation::simulate_imu_stream(walk, imu, t0 - 0.1, t0 + spacing * kKeyframes);

  std::array<SE3, kKeyframes> truth;
  for (int k = 0; k < kKeyframes; ++k) {
    const simulation::KinematicState s = walk.state(t0 + spacing * k);
    truth[k] = s.T_W_B;
    const Vec3 dt = noise3(0.02);  // drawn last argument first: the order of record (random_draws.hpp)
    pose_to_block(SE3(s.T_W_B.q * Quat(Eigen::AngleAxisd(0.01, noise3(1.0).normalized())), s.T_W_B.t + dt),
                  w.pose[k].data());
    Eigen::Map<Eigen::Matrix<double, 9, 1>>(w.speed_bias[k].data()) << s.v_W + noise3(0.02), noise3(1e-3),
        noise3(1e-2);
  }
  Mat3 R_B_C;
  R_B_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // camera looking forward
  const SE3 T_B_C(Quat(R_B_C), Vec3(0.05, 0.0, 0.02));
  pose_to_block(T_B_C, w.extrinsic.data());

  const auto add = [&](MarginalizationTerm term) {
    ++w.factors;
    std::vector<int> leaving;
    for (std::size_t i = 0; i < term.blocks.size(); ++i) {
      const double* b = term.blocks[i];
      const bool is_lambda = b >= w.lambda.data() && b < w.lambda.data() + kAnchoredInOldest;
      if (b == w.pose[0].data() || b == w.speed_bias[0].data() || is_lambda) leaving.push_back(static_cast<int>(i));
    }
    if (leaving.empty()) return;
    term.marginalize = leaving;
    w.oldest_terms.push_back(std::move(term));
  };

  for (int k = 0; k + 1 < kKeyframes; ++k) {
    const ImuPreintegration pre = ImuPreintegration::between(
        stream.samples, seconds_to_ns(t0 + spacing * k), seconds_to_ns(t0 + spacing * (k + 1)),
        ImuNoise::from(calibration), Vec3::Zero(), Vec3::Zero());
    add({std::make_shared<ImuFactor>(pre), nullptr,
         {w.pose[k].data(), w.speed_bias[k].data(), w.pose[k + 1].data(), w.speed_bias[k + 1].data()}, {}});
  }
  std::vector<double*> prior_blocks;
  std::vector<BlockKind> prior_kinds;
  for (auto& p : w.pose) {
    prior_blocks.push_back(p.data());
    prior_kinds.push_back(BlockKind::kPose);
  }
  for (int k = 0; k < 2; ++k) {
    prior_blocks.push_back(w.speed_bias[k].data());
    prior_kinds.push_back(BlockKind::kEuclidean);
  }
  add({std::make_shared<MarginalizationFactor>(previous_prior(prior_blocks, prior_kinds, rng)), nullptr, prior_blocks,
       {}});

  const double sigma_lambda = inverse_depth_sigma(0.2, kFocal, 0.05);
  const auto cauchy = std::make_shared<ceres::CauchyLoss>(1.0);
  std::uniform_real_distribution<double> xy(-0.45, 0.45), depth(2.0, 8.0);
  std::uniform_int_distribution<int> first_other(1, kKeyframes - 3), length(3, kKeyframes);
  for (int f = 0; f < kFeatures; ++f) {
    const int a = f < kAnchoredInOldest ? 0 : first_other(rng);
    const int last = std::min(kKeyframes - 1, a + length(rng) - 1);
    const double z = depth(rng);
    const double y = xy(rng) * z;  // y before x: the order of record (random_draws.hpp)
    const Vec3 P_ca(xy(rng) * z, y, z);
    const Vec3 P_w = truth[a] * (T_B_C * P_ca);
    const Eigen::Vector2d m_a = P_ca.head<2>() / z + draw_vector<2>([&] { return normal(rng); }) * kSigmaPx / kFocal;
    w.lambda[f] = (1.0 + 0.03 * normal(rng)) / z;
    add({std::make_shared<InverseDepthFactor>(z * (1.0 + 0.01 * normal(rng)), sigma_lambda), nullptr,
         {&w.lambda[f]}, {}});
    for (int t = a + 1; t <= last; ++t) {
      const Vec3 P_ct = T_B_C.inverse() * (truth[t].inverse() * P_w);
      if (P_ct.z() < 0.5) break;  // walked past it
      const Eigen::Vector2d m_t =
          P_ct.head<2>() / P_ct.z() + draw_vector<2>([&] { return normal(rng); }) * kSigmaPx / kFocal;
      const std::vector<double*> blocks{w.pose[a].data(), w.pose[t].data(), w.extrinsic.data(), &w.lambda[f]};
      add({std::make_shared<ReprojectionFactor>(m_a, m_t, kFocal, kSigmaPx), cauchy, blocks, {}});
      add({std::make_shared<Depth3dFactor>(m_a, m_t, P_ct.z() * (1.0 + 0.01 * normal(rng)), kFocal, sigma_lambda,
                                           kSigmaPx),
           cauchy, blocks, {}});
    }
  }
}

Marginalizer marginalizer_for(Window& w) {
  Marginalizer m;
  for (auto& p : w.pose) m.set_manifold(p.data(), BlockKind::kPose);
  m.set_manifold(w.extrinsic.data(), BlockKind::kPose);
  for (const MarginalizationTerm& term : w.oldest_terms) m.add(term);
  return m;
}

void BM_MarginalizeOldestKeyframe(benchmark::State& state) {
  Window w;
  make_window(w);
  MarginalizationPrior prior;
  for (auto _ : state) {
    prior = marginalizer_for(w).marginalize();
    benchmark::DoNotOptimize(prior.J.data());
  }
  state.counters["terms"] = static_cast<double>(w.oldest_terms.size());
  state.counters["window_factors"] = static_cast<double>(w.factors);
  state.counters["kept_dim"] = prior.tangent_size();
  state.counters["prior_rank"] = static_cast<double>(prior.J.rows());
}
BENCHMARK(BM_MarginalizeOldestKeyframe)->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);

void BM_PriorFactorEvaluate(benchmark::State& state) {
  Window w;
  make_window(w);
  const auto prior = std::make_shared<const MarginalizationPrior>(marginalizer_for(w).marginalize());
  const MarginalizationFactor factor(prior);
  std::vector<std::vector<double>> jacobian_storage;
  std::vector<double*> jacobians;
  for (int size : factor.parameter_block_sizes()) {
    jacobian_storage.emplace_back(static_cast<std::size_t>(size) * factor.num_residuals());
    jacobians.push_back(jacobian_storage.back().data());
  }
  w.pose[3][0] += 0.01;  // away from the linearization point
  std::vector<double> residuals(factor.num_residuals());
  for (auto _ : state) {
    benchmark::DoNotOptimize(factor.Evaluate(prior->blocks.data(), residuals.data(), jacobians.data()));
  }
}
BENCHMARK(BM_PriorFactorEvaluate)->Unit(benchmark::kMicrosecond);

}  // namespace
