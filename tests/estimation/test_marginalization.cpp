// Marginalization prior: Schur complement, equivalence with the full problem, the prior factor's
// Jacobians and manifold minus, address remapping, singular cases.
#include "navaid/estimation/marginalization.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/imu_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/landmark_factors.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/simulation/imu_model.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

using testing::jacobians_match;
using testing::random_pose;
using testing::random_rotation;
using testing::random_vector;

constexpr double kMarginalFocal = 460.0;
constexpr double kMarginalSigmaPx = 1.5;

// ---------------------------------------------------------------------------------------------
// Helpers independent of the code under test: dense Jacobians from Ceres' own Problem::Evaluate.

struct Factor {
  std::shared_ptr<const ceres::CostFunction> cost;
  std::shared_ptr<const ceres::LossFunction> loss;
  std::vector<double*> blocks;
  bool touches(const double* block) const { return std::find(blocks.begin(), blocks.end(), block) != blocks.end(); }
};

struct Linearization {
  Eigen::MatrixXd J;  // tangent columns, in the order of the requested blocks
  Eigen::VectorXd r;
};

// A Problem that does not own the shared factors; pose blocks get the PoseManifold.
std::unique_ptr<ceres::Problem> make_problem(const std::vector<Factor>& factors, const std::vector<double*>& poses,
                                             const std::vector<double*>& constants = {}) {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  auto problem = std::make_unique<ceres::Problem>(options);
  for (const Factor& f : factors) {
    problem->AddResidualBlock(const_cast<ceres::CostFunction*>(f.cost.get()),
                              const_cast<ceres::LossFunction*>(f.loss.get()), f.blocks);
  }
  for (double* pose : poses) {
    if (problem->HasParameterBlock(pose)) problem->SetManifold(pose, make_pose_manifold().release());
  }
  for (double* block : constants) {
    if (problem->HasParameterBlock(block)) problem->SetParameterBlockConstant(block);
  }
  return problem;
}

Linearization linearize(ceres::Problem& problem, const std::vector<double*>& order) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = order;
  options.apply_loss_function = true;
  double cost = 0.0;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  EXPECT_TRUE(problem.Evaluate(options, &cost, &residuals, nullptr, &crs));
  Linearization lin;
  lin.J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) lin.J(row, crs.cols[k]) = crs.values[k];
  }
  lin.r = Eigen::Map<Eigen::VectorXd>(residuals.data(), static_cast<Eigen::Index>(residuals.size()));
  return lin;
}

int tangent_columns(const std::vector<double*>& blocks, const ceres::Problem& problem) {
  int n = 0;
  for (double* b : blocks) n += problem.ParameterBlockTangentSize(b);
  return n;
}

std::string scientific(double value) {
  std::ostringstream out;
  out << std::scientific << std::setprecision(2) << value;
  return out.str();
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

// ---------------------------------------------------------------------------------------------
// A small visual-inertial batch: 3 keyframes of a simulated walk (noisy IMU with bias walk),
// features anchored in keyframes 0 and 1 with reprojection (Cauchy), inverse-depth and 3D depth
// factors, and a prior on the first pose.

// Builds a MarginalizationPrior by hand: a Gaussian prior on one block around its current value.
std::shared_ptr<MarginalizationPrior> gaussian_prior(double* block, BlockKind kind, int ambient_size,
                                                     const Eigen::VectorXd& sigmas) {
  auto prior = std::make_shared<MarginalizationPrior>();
  prior->blocks = {block};
  prior->kinds = {kind};
  prior->ambient_sizes = {ambient_size};
  prior->tangent_offsets = {0};
  prior->x0 = {std::vector<double>(block, block + ambient_size)};
  prior->J = sigmas.cwiseInverse().asDiagonal();
  prior->r = Eigen::VectorXd::Zero(sigmas.size());
  return prior;
}

struct Batch {
  static constexpr int kKeyframes = 3;
  std::array<std::array<double, kPoseSize>, kKeyframes> pose{};
  std::array<std::array<double, kSpeedBiasSize>, kKeyframes> speed_bias{};
  std::array<double, kPoseSize> extrinsic{};
  std::vector<std::array<double, 1>> lambda;  // sized once: blocks must not move
  std::vector<int> anchor;                    // keyframe of each feature
  std::vector<std::array<double, kLandmarkSize>> landmark;  // 3-parameter features, sized once
  std::vector<int> landmark_anchor;
  std::vector<Factor> factors;

  std::vector<double*> pose_blocks() {
    std::vector<double*> p;
    for (auto& x : pose) p.push_back(x.data());
    p.push_back(extrinsic.data());
    return p;
  }
  // The states keyframe 0 takes with it: its pose, speed-bias and the features anchored there.
  std::vector<double*> leaving() {
    std::vector<double*> m{pose[0].data(), speed_bias[0].data()};
    for (std::size_t f = 0; f < lambda.size(); ++f) {
      if (anchor[f] == 0) m.push_back(lambda[f].data());
    }
    for (std::size_t f = 0; f < landmark_anchor.size(); ++f) {
      if (landmark_anchor[f] == 0) m.push_back(landmark[f].data());
    }
    return m;
  }
};

Batch make_batch(std::uint64_t seed) {
  Batch batch;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto noise3 = [&](double sigma) -> Vec3 { return draw_vector<3>([&] { return normal(rng); }) * sigma; };

  const simulation::WalkerTrajectory walk({{0.0, 0.0}, {8.0, 0.0}, {8.0, 6.0}});
  simulation::ImuModelOptions imu_options;
  imu_options.seed = seed;
  imu_options.initial_gyro_bias = Vec3(0.004, -0.003, 0.002);
  imu_options.initial_accel_bias = Vec3(0.05, -0.04, 0.03);
  simulation::ImuModel imu(navaid::testing::euroc_imu_calibration(), imu_options);
  const auto stream = simulation::simulate_imu_stream(walk, imu, 1.9, 3.1);

  const std::array<double, Batch::kKeyframes> times{2.0, 2.4, 2.8};
  std::array<SE3, Batch::kKeyframes> truth;
  for (int k = 0; k < Batch::kKeyframes; ++k) {
    const simulation::KinematicState s = walk.state(times[k]);
    truth[k] = s.T_W_B;
    // Estimates near the truth (the window's state is never exact); the translation's noise drawn
    // first, the last argument first: the order of record (random_draws.hpp).
    const Vec3 dt = noise3(0.02);
    pose_to_block(SE3(s.T_W_B.q * Quat(Eigen::AngleAxisd(0.01, noise3(1.0).normalized())), s.T_W_B.t + dt),
                  batch.pose[k].data());
    Eigen::Map<Eigen::Matrix<double, 9, 1>> sb(batch.speed_bias[k].data());
    sb << s.v_W + noise3(0.02), imu_options.initial_gyro_bias + noise3(1e-3),
        imu_options.initial_accel_bias + noise3(1e-2);
  }
  // Camera looking forward: z_C = x_B, x_C = -y_B, y_C = -z_B.
  Mat3 R_B_C;
  R_B_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const SE3 T_B_C(Quat(R_B_C), Vec3(0.05, 0.0, 0.02));
  pose_to_block(T_B_C, batch.extrinsic.data());

  for (int k = 0; k + 1 < Batch::kKeyframes; ++k) {
    const ImuPreintegration pre =
        ImuPreintegration::between(stream.samples, seconds_to_ns(times[k]), seconds_to_ns(times[k + 1]),
                                   ImuNoise::from(navaid::testing::euroc_imu_calibration()), Vec3::Zero(), Vec3::Zero());
    batch.factors.push_back({std::make_shared<ImuFactor>(pre), nullptr,
                             {batch.pose[k].data(), batch.speed_bias[k].data(), batch.pose[k + 1].data(),
                              batch.speed_bias[k + 1].data()}});
  }
  // Priors on the first keyframe (as the previous marginalization would leave): the pose prior
  // holds the gauge (position and yaw), the speed-bias prior the weakly observable biases.
  Eigen::VectorXd pose_sigma(6), speed_bias_sigma(9);
  pose_sigma << 0.01, 0.01, 0.01, 0.005, 0.005, 0.005;
  speed_bias_sigma << 0.1, 0.1, 0.1, 0.005, 0.005, 0.005, 0.05, 0.05, 0.05;
  batch.factors.push_back(
      {std::make_shared<MarginalizationFactor>(gaussian_prior(batch.pose[0].data(), BlockKind::kPose, kPoseSize, pose_sigma)),
       nullptr, {batch.pose[0].data()}});
  batch.factors.push_back({std::make_shared<MarginalizationFactor>(gaussian_prior(
                               batch.speed_bias[0].data(), BlockKind::kEuclidean, kSpeedBiasSize, speed_bias_sigma)),
                           nullptr, {batch.speed_bias[0].data()}});

  const double sigma_lambda = inverse_depth_sigma(0.2, kMarginalFocal, 0.05);
  const auto cauchy = std::make_shared<ceres::CauchyLoss>(1.0);
  constexpr int kFeatures = 12;
  batch.lambda.resize(kFeatures);
  std::uniform_real_distribution<double> xy(-0.5, 0.5), depth(2.0, 7.0);
  const double pixel = kMarginalSigmaPx / kMarginalFocal;
  for (int f = 0; f < kFeatures; ++f) {
    const int a = f % 2;  // anchors in keyframes 0 and 1
    batch.anchor.push_back(a);
    const double z = depth(rng);
    const double y = xy(rng) * z;  // y before x: the order of record (random_draws.hpp)
    const Vec3 P_ca(xy(rng) * z, y, z);
    const Vec3 P_w = truth[a] * (T_B_C * P_ca);
    const Eigen::Vector2d m_a = P_ca.head<2>() / z + draw_vector<2>([&] { return normal(rng); }) * pixel;
    batch.lambda[f][0] = (1.0 / z) * (1.0 + 0.03 * normal(rng));
    batch.factors.push_back({std::make_shared<InverseDepthFactor>(z + 0.02 * normal(rng), sigma_lambda), nullptr,
                             {batch.lambda[f].data()}});
    for (int t = a + 1; t < Batch::kKeyframes; ++t) {
      const Vec3 P_ct = T_B_C.inverse() * (truth[t].inverse() * P_w);
      const Eigen::Vector2d m_t = P_ct.head<2>() / P_ct.z() + draw_vector<2>([&] { return normal(rng); }) * pixel;
      const std::vector<double*> blocks{batch.pose[a].data(), batch.pose[t].data(), batch.extrinsic.data(),
                                        batch.lambda[f].data()};
      batch.factors.push_back({std::make_shared<ReprojectionFactor>(m_a, m_t, kMarginalFocal, kMarginalSigmaPx), cauchy, blocks});
      if ((f + t) % 2 == 0) {
        batch.factors.push_back({std::make_shared<Depth3dFactor>(m_a, m_t, P_ct.z() * (1.0 + 0.01 * normal(rng)),
                                                                 kMarginalFocal, sigma_lambda, kMarginalSigmaPx),
                                 cauchy, blocks});
      }
    }
  }
  return batch;
}

// The marginalizer fed with every factor that touches a leaving block.
Marginalizer marginalizer_for(Batch& batch, const std::vector<double*>& leaving,
                              const std::vector<double*>& constants = {}) {
  Marginalizer marginalizer;
  for (double* block : constants) marginalizer.set_constant(block);
  for (double* pose : batch.pose_blocks()) marginalizer.set_manifold(pose, BlockKind::kPose);
  for (const Factor& f : batch.factors) {
    MarginalizationTerm term{f.cost, f.loss, f.blocks, {}};
    for (std::size_t i = 0; i < f.blocks.size(); ++i) {
      if (std::find(leaving.begin(), leaving.end(), f.blocks[i]) != leaving.end()) {
        term.marginalize.push_back(static_cast<int>(i));
      }
    }
    if (!term.marginalize.empty()) marginalizer.add(term);
  }
  return marginalizer;
}

// Independent Schur complement: Ceres' tangent Jacobian of the same factors, dense H, full inverse.
void expect_prior_is_schur_complement(Batch& batch, const MarginalizationPrior& prior, double tol,
                                      const std::vector<double*>& constants = {}) {
  const std::vector<double*> leaving = batch.leaving();
  std::vector<Factor> terms;
  for (const Factor& f : batch.factors) {
    if (std::any_of(leaving.begin(), leaving.end(), [&](double* b) { return f.touches(b); })) terms.push_back(f);
  }
  auto problem = make_problem(terms, batch.pose_blocks(), constants);
  std::vector<double*> order = leaving;
  order.insert(order.end(), prior.blocks.begin(), prior.blocks.end());
  const Linearization lin = linearize(*problem, order);
  const int m = tangent_columns(leaving, *problem);
  const int k = tangent_columns(prior.blocks, *problem);
  ASSERT_EQ(k, prior.tangent_size());
  ASSERT_EQ(lin.J.cols(), m + k);
  const Eigen::MatrixXd H = lin.J.transpose() * lin.J;
  const Eigen::VectorXd b = lin.J.transpose() * lin.r;
  const Eigen::MatrixXd Hmm_inv = H.topLeftCorner(m, m).inverse();
  const Eigen::MatrixXd H_star = H.bottomRightCorner(k, k) - H.bottomLeftCorner(k, m) * Hmm_inv * H.topRightCorner(m, k);
  const Eigen::VectorXd b_star = b.tail(k) - H.bottomLeftCorner(k, m) * Hmm_inv * b.head(m);
  const double err_H = relative_difference(prior.information(), H_star);
  const double err_b = relative_difference(prior.gradient(), b_star);
  EXPECT_LT(err_H, tol);
  EXPECT_LT(err_b, tol);
  // The prior keeps exactly the numerically nonzero directions of H*.
  const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H_star).eigenvalues();
  const double threshold = 1e-10 * eigenvalues(eigenvalues.size() - 1);  // ascending
  EXPECT_EQ(prior.J.rows(), (eigenvalues.array() > threshold).count());
  ::testing::Test::RecordProperty("schur_information_relative_error", scientific(err_H));
  ::testing::Test::RecordProperty("schur_gradient_relative_error", scientific(err_b));
}

void solve(ceres::Problem& problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
}

TEST(Marginalization, PriorIsTheSchurComplementOfTheFullHessian) {
  Batch batch = make_batch(11);
  const MarginalizationPrior prior = marginalizer_for(batch, batch.leaving()).marginalize();
  // Kept: pose 1 and speed-bias 1 (IMU), poses 1, 2, the extrinsic (reprojections): 6 + 9 + 6 + 6.
  EXPECT_EQ(prior.blocks.size(), 4u);
  EXPECT_EQ(prior.tangent_size(), 27);
  // Keyframe 0's velocity and biases leave with it, so the IMU factor constrains (pose 1,
  // speed-bias 1) only in 6 of 15 directions: the prior is rank deficient (checked in the helper).
  EXPECT_LT(prior.J.rows(), 27);
  expect_prior_is_schur_complement(batch, prior, 1e-8);
  for (std::size_t i = 0; i < prior.blocks.size(); ++i) {
    EXPECT_TRUE(std::equal(prior.x0[i].begin(), prior.x0[i].end(), prior.blocks[i]));
  }
}

// Features as 3-parameter landmarks [x_a, y_a, lambda] (estimated anchor bearing), eliminated
// on the poses that see them (the fixed-size path); one more seen by its anchor bearing alone
// (depth unobserved: the pseudo-inverse) adds nothing to the prior.
TEST(Marginalization, ThreeParameterLandmarksGiveTheSchurComplement) {
  Batch batch = make_batch(21);
  std::mt19937_64 rng(21);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> xy(-0.5, 0.5), depth(2.0, 7.0);
  const double pixel = kMarginalSigmaPx / kMarginalFocal;
  const double sigma_lambda = inverse_depth_sigma(0.2, kMarginalFocal, 0.05);
  const auto cauchy = std::make_shared<ceres::CauchyLoss>(1.0);
  constexpr int kLandmarks = 10;
  batch.landmark.resize(kLandmarks + 1);
  SE3 T_B_C;
  T_B_C = pose_from_block(batch.extrinsic.data());
  for (int f = 0; f < kLandmarks; ++f) {
    const int a = f % 2;
    batch.landmark_anchor.push_back(a);
    const SE3 T_W_Ca = pose_from_block(batch.pose[a].data()) * T_B_C;
    const double z = depth(rng);
    const double y = xy(rng) * z;  // y before x: the order of record (random_draws.hpp)
    const Vec3 P_ca(xy(rng) * z, y, z);
    const Vec3 P_w = T_W_Ca * P_ca;
    const Eigen::Vector2d m_a = P_ca.head<2>() / z + draw_vector<2>([&] { return normal(rng); }) * pixel;
    auto& l = batch.landmark[f];
    l = {m_a.x(), m_a.y(), (1.0 / z) * (1.0 + 0.03 * normal(rng))};
    batch.factors.push_back({std::make_shared<AnchorBearingFactor>(m_a, kMarginalFocal, kMarginalSigmaPx), nullptr, {l.data()}});
    batch.factors.push_back(
        {std::make_shared<AnchorInverseDepthFactor>(z + 0.02 * normal(rng), sigma_lambda), nullptr, {l.data()}});
    for (int t = a + 1; t < Batch::kKeyframes; ++t) {
      const SE3 T_W_Ct = pose_from_block(batch.pose[t].data()) * T_B_C;
      const Vec3 P_ct = T_W_Ct.inverse() * P_w;
      const Eigen::Vector2d m_t = P_ct.head<2>() / P_ct.z() + draw_vector<2>([&] { return normal(rng); }) * pixel;
      batch.factors.push_back({std::make_shared<LandmarkReprojectionFactor>(m_t, kMarginalFocal, kMarginalSigmaPx), cauchy,
                               {batch.pose[a].data(), batch.pose[t].data(), batch.extrinsic.data(), l.data()}});
    }
  }
  const MarginalizationPrior prior = marginalizer_for(batch, batch.leaving()).marginalize();
  expect_prior_is_schur_complement(batch, prior, 1e-8);

  auto& unobserved = batch.landmark[kLandmarks];
  unobserved = {0.1, -0.2, 0.3};
  batch.landmark_anchor.push_back(0);
  batch.factors.push_back(
      {std::make_shared<AnchorBearingFactor>(Eigen::Vector2d(0.1, -0.2), kMarginalFocal, kMarginalSigmaPx), nullptr, {unobserved.data()}});
  const MarginalizationPrior with_unobserved = marginalizer_for(batch, batch.leaving()).marginalize();
  EXPECT_LT(relative_difference(with_unobserved.information(), prior.information()), 1e-12);
  EXPECT_LT(relative_difference(with_unobserved.gradient(), prior.gradient()), 1e-12);
}

TEST(Marginalization, RobustWeightingMatchesCeresIncludingTheTriggsCorrection) {
  // TolerantLoss has rho'' > 0, so Ceres uses the second-order (alpha) correction, not sqrt(rho').
  Batch batch = make_batch(12);
  const auto tolerant = std::make_shared<ceres::TolerantLoss>(0.5, 0.3);
  for (Factor& f : batch.factors) {
    if (f.loss) f.loss = tolerant;
  }
  expect_prior_is_schur_complement(batch, marginalizer_for(batch, batch.leaving()).marginalize(), 1e-8);
}

TEST(Marginalization, PriorPlusRemainingFactorsKeepsTheFullOptimum) {
  // Three keyframes cannot calibrate the camera: the extrinsic is held constant here.
  Batch batch = make_batch(13);
  const std::vector<double*> constants{batch.extrinsic.data()};
  auto full = make_problem(batch.factors, batch.pose_blocks(), constants);
  solve(*full);
  const auto optimum = batch;  // copies the state values (the factors are shared, unchanged)

  const std::vector<double*> leaving = batch.leaving();
  auto prior = std::make_shared<MarginalizationPrior>(marginalizer_for(batch, leaving, constants).marginalize());
  expect_prior_is_schur_complement(batch, *prior, 1e-8, constants);
  std::vector<Factor> reduced;
  for (const Factor& f : batch.factors) {
    if (std::none_of(leaving.begin(), leaving.end(), [&](double* b) { return f.touches(b); })) reduced.push_back(f);
  }
  reduced.push_back({std::make_shared<MarginalizationFactor>(prior), nullptr, prior->blocks});

  // Start the reduced problem away from the optimum: it must come back.
  std::mt19937_64 rng(5);
  for (int k = 1; k < Batch::kKeyframes; ++k) {
    const SE3 T = pose_from_block(batch.pose[k].data());
    const Vec3 dt = random_vector(rng, 0.03);  // drawn last argument first: the order of record (random_draws.hpp)
    pose_to_block(SE3(T.q * random_rotation(rng, 0.02), T.t + dt), batch.pose[k].data());
    for (double& v : batch.speed_bias[k]) v += 0.01;
  }
  for (auto& l : batch.lambda) l[0] *= 1.05;
  auto problem = make_problem(reduced, batch.pose_blocks(), constants);
  solve(*problem);

  double max_position = 0.0, max_angle = 0.0, max_other = 0.0;
  for (int k = 1; k < Batch::kKeyframes; ++k) {
    const SE3 a = pose_from_block(batch.pose[k].data()), b = pose_from_block(optimum.pose[k].data());
    max_position = std::max(max_position, (a.t - b.t).norm());
    max_angle = std::max(max_angle, a.q.angularDistance(b.q));
    for (int i = 0; i < kSpeedBiasSize; ++i) {
      max_other = std::max(max_other, std::abs(batch.speed_bias[k][i] - optimum.speed_bias[k][i]));
    }
  }
  for (std::size_t f = 0; f < batch.lambda.size(); ++f) {
    if (batch.anchor[f] != 0) max_other = std::max(max_other, std::abs(batch.lambda[f][0] - optimum.lambda[f][0]));
  }
  const SE3 e = pose_from_block(batch.extrinsic.data()), e0 = pose_from_block(optimum.extrinsic.data());
  max_position = std::max(max_position, (e.t - e0.t).norm());
  max_angle = std::max(max_angle, e.q.angularDistance(e0.q));
  EXPECT_LT(max_position, 1e-7);
  EXPECT_LT(max_angle, 1e-7);
  EXPECT_LT(max_other, 1e-7);
  RecordProperty("max_position_difference_m", scientific(max_position));
  RecordProperty("max_angle_difference_rad", scientific(max_angle));
}

TEST(Marginalization, SequentialMarginalizationEqualsJointMarginalization) {
  // Keyframe 0 out, then keyframe 1 with the first prior as one of its terms, must leave the same
  // prior as taking both out at once (same linearization point: the prior factor's tangent
  // Jacobian at x0 is J_p itself).
  Batch batch = make_batch(19);
  std::vector<double*> first = batch.leaving();
  std::vector<double*> second{batch.pose[1].data(), batch.speed_bias[1].data()};
  for (std::size_t f = 0; f < batch.lambda.size(); ++f) {
    if (batch.anchor[f] == 1) second.push_back(batch.lambda[f].data());
  }
  const auto prior1 = std::make_shared<MarginalizationPrior>(marginalizer_for(batch, first).marginalize());

  // Keyframe 0's factors are replaced by its prior (same blocks: swap the factor list).
  const std::vector<Factor> all_factors = batch.factors;
  batch.factors.clear();
  for (const Factor& f : all_factors) {
    if (std::none_of(first.begin(), first.end(), [&](double* b) { return f.touches(b); })) batch.factors.push_back(f);
  }
  batch.factors.push_back({std::make_shared<MarginalizationFactor>(prior1), nullptr, prior1->blocks});
  const MarginalizationPrior sequential = marginalizer_for(batch, second).marginalize();
  batch.factors = all_factors;

  std::vector<double*> both = first;
  both.insert(both.end(), second.begin(), second.end());
  const MarginalizationPrior joint = marginalizer_for(batch, both).marginalize();

  ASSERT_EQ(sequential.tangent_size(), joint.tangent_size());
  // Same blocks, possibly in another order: compare through a column permutation.
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(joint.tangent_size(), joint.tangent_size());
  for (std::size_t i = 0; i < joint.blocks.size(); ++i) {
    const int j = sequential.index_of(joint.blocks[i]);
    ASSERT_NE(j, -1);
    const int n = tangent_size(joint.kinds[i], joint.ambient_sizes[i]);
    P.block(sequential.tangent_offsets[j], joint.tangent_offsets[i], n, n).setIdentity();
  }
  EXPECT_LT(relative_difference(P.transpose() * sequential.information() * P, joint.information()), 1e-8);
  EXPECT_LT(relative_difference(P.transpose() * sequential.gradient(), joint.gradient()), 1e-8);
}

// ---------------------------------------------------------------------------------------------
// Linear-Gaussian factors r = sum_i A_i x_i + c: marginalization is then exact.

class LinearCost final : public ceres::CostFunction {
 public:
  LinearCost(std::vector<Eigen::MatrixXd> A, Eigen::VectorXd c) : A_(std::move(A)), c_(std::move(c)) {
    set_num_residuals(static_cast<int>(c_.size()));
    for (const auto& a : A_) mutable_parameter_block_sizes()->push_back(static_cast<int>(a.cols()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, c_.size());
    r = c_;
    for (std::size_t i = 0; i < A_.size(); ++i) {
      r += A_[i] * Eigen::Map<const Eigen::VectorXd>(x[i], A_[i].cols());
      if (jacobians != nullptr && jacobians[i] != nullptr) {
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[i], A_[i].rows(),
                                                                                          A_[i].cols()) = A_[i];
      }
    }
    return true;
  }

 private:
  std::vector<Eigen::MatrixXd> A_;
  Eigen::VectorXd c_;
};

struct LinearSystem {
  std::vector<std::vector<double>> x;  // blocks
  std::vector<Factor> factors;
};

// Blocks of sizes 3, 2, 4, 1, 3, 2 in a chain plus a few long links; rows >= columns per factor.
LinearSystem make_linear_system(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  LinearSystem s;
  const std::vector<int> sizes{3, 2, 4, 1, 3, 2};
  s.x.reserve(sizes.size());
  for (int n : sizes) {
    s.x.emplace_back(n);
    for (double& v : s.x.back()) v = normal(rng);
  }
  const std::vector<std::vector<int>> links{{0}, {0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {0, 2, 4}, {1, 5}, {5}};
  for (const auto& link : links) {
    int cols = 0;
    for (int i : link) cols += sizes[i];
    const int rows = cols + 1;
    std::vector<Eigen::MatrixXd> A;
    std::vector<double*> blocks;
    for (int i : link) {
      A.push_back(Eigen::MatrixXd::NullaryExpr(rows, sizes[i], [&]() { return normal(rng); }));
      blocks.push_back(s.x[i].data());
    }
    const Eigen::VectorXd c = Eigen::VectorXd::NullaryExpr(rows, [&]() { return normal(rng); });
    s.factors.push_back({std::make_shared<LinearCost>(A, c), nullptr, blocks});
  }
  return s;
}

// The exact least-squares minimizer over `blocks` (one Gauss-Newton step of a linear problem).
Eigen::VectorXd linear_optimum(const std::vector<Factor>& factors, const std::vector<double*>& blocks) {
  auto problem = make_problem(factors, {});
  const Linearization lin = linearize(*problem, blocks);
  const Eigen::VectorXd step = (lin.J.transpose() * lin.J).ldlt().solve(-lin.J.transpose() * lin.r);
  Eigen::VectorXd x(step.size());
  int offset = 0;
  for (double* b : blocks) {
    const int n = problem->ParameterBlockSize(b);
    x.segment(offset, n) = Eigen::Map<const Eigen::VectorXd>(b, n) + step.segment(offset, n);
    offset += n;
  }
  return x;
}

TEST(Marginalization, LinearFactorsGiveExactlyTheFullSolution) {
  LinearSystem s = make_linear_system(21);
  const std::vector<double*> leaving{s.x[0].data(), s.x[2].data()};
  Marginalizer marginalizer;
  std::vector<Factor> reduced;
  for (const Factor& f : s.factors) {
    MarginalizationTerm term{f.cost, nullptr, f.blocks, {}};
    for (std::size_t i = 0; i < f.blocks.size(); ++i) {
      if (std::find(leaving.begin(), leaving.end(), f.blocks[i]) != leaving.end()) term.marginalize.push_back(int(i));
    }
    if (term.marginalize.empty()) {
      reduced.push_back(f);
    } else {
      marginalizer.add(term);
    }
  }
  auto prior = std::make_shared<MarginalizationPrior>(marginalizer.marginalize());
  ASSERT_EQ(prior->blocks.size(), 3u);  // x1, x3, x4 (x5 shares no factor with x0, x2)
  reduced.push_back({std::make_shared<MarginalizationFactor>(prior), nullptr, prior->blocks});

  std::vector<double*> all{s.x[0].data(), s.x[2].data()};
  all.insert(all.end(), prior->blocks.begin(), prior->blocks.end());
  const Eigen::VectorXd full = linear_optimum(s.factors, all);
  // The reduced problem is solved from another point: the prior is exact, not only at x0.
  for (double* b : prior->blocks) b[0] += 0.7;
  const Eigen::VectorXd kept = linear_optimum(reduced, prior->blocks);
  const Eigen::VectorXd expected = full.tail(kept.size());
  EXPECT_LT((kept - expected).norm() / expected.norm(), 1e-9);
}

TEST(Marginalization, SingularMarginalBlockUsesThePseudoInverse) {
  // x0 (3) is observed only along its first two axes and x1 (2) not at all: H_mm has rank 2 of 5.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x0{0.1, 0.2, 0.3}, x1{1.0, -1.0}, y{0.5, 0.4};
  Eigen::MatrixXd A0 = Eigen::MatrixXd::NullaryExpr(4, 3, [&]() { return normal(rng); });
  A0.col(2).setZero();
  const Eigen::MatrixXd A1 = Eigen::MatrixXd::Zero(4, 2);
  const Eigen::MatrixXd Ay = Eigen::MatrixXd::NullaryExpr(4, 2, [&]() { return normal(rng); });
  const Eigen::VectorXd c = Eigen::VectorXd::NullaryExpr(4, [&]() { return normal(rng); });
  const Eigen::MatrixXd By = Eigen::MatrixXd::NullaryExpr(3, 2, [&]() { return normal(rng); });
  const Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(3, [&]() { return normal(rng); });

  Marginalizer marginalizer;
  marginalizer.add({std::make_shared<LinearCost>(std::vector<Eigen::MatrixXd>{A0, A1, Ay}, c), nullptr,
                    {x0.data(), x1.data(), y.data()}, {0, 1}});
  marginalizer.add({std::make_shared<LinearCost>(std::vector<Eigen::MatrixXd>{By}, d), nullptr, {y.data()}, {}});
  const MarginalizationPrior prior = marginalizer.marginalize();
  ASSERT_TRUE(prior.J.allFinite());
  ASSERT_TRUE(prior.r.allFinite());

  // Independently: stack the Jacobian at the current values and use a complete orthogonal
  // decomposition's pseudo-inverse of H_mm.
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(7, 7);
  J.topLeftCorner(4, 3) = A0;
  J.block(0, 5, 4, 2) = Ay;
  J.bottomRightCorner(3, 2) = By;
  Eigen::VectorXd r(7);
  r << c + A0 * Eigen::Map<Eigen::VectorXd>(x0.data(), 3) + Ay * Eigen::Map<Eigen::VectorXd>(y.data(), 2),
      d + By * Eigen::Map<Eigen::VectorXd>(y.data(), 2);
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::VectorXd b = J.transpose() * r;
  const Eigen::MatrixXd Hmm_pinv = H.topLeftCorner(5, 5).completeOrthogonalDecomposition().pseudoInverse();
  const Eigen::MatrixXd H_star = H.bottomRightCorner(2, 2) - H.bottomLeftCorner(2, 5) * Hmm_pinv * H.topRightCorner(5, 2);
  const Eigen::VectorXd b_star = b.tail(2) - H.bottomLeftCorner(2, 5) * Hmm_pinv * b.head(5);
  EXPECT_LT(relative_difference(prior.information(), H_star), 1e-10);
  EXPECT_LT(relative_difference(prior.gradient(), b_star), 1e-10);
}

TEST(Marginalization, UnobservedDirectionsLeaveARankDeficientPriorWithoutNaN) {
  // Without the first-pose prior nothing fixes position and yaw: the kept information is singular.
  Batch batch = make_batch(14);
  batch.factors.erase(std::remove_if(batch.factors.begin(), batch.factors.end(),
                                     [](const Factor& f) {
                                       return dynamic_cast<const MarginalizationFactor*>(f.cost.get()) != nullptr;
                                     }),
                      batch.factors.end());
  const MarginalizationPrior prior = marginalizer_for(batch, batch.leaving()).marginalize();
  EXPECT_TRUE(prior.J.allFinite());
  EXPECT_TRUE(prior.r.allFinite());
  // At least position (3) and yaw (1) of the whole batch are free.
  EXPECT_LE(prior.J.rows(), prior.tangent_size() - 4);
  const Eigen::MatrixXd H = prior.information();
  EXPECT_LT(relative_difference(H, H.transpose()), 1e-14);
  expect_prior_is_schur_complement(batch, prior, 1e-8);
}

TEST(Marginalization, MarginalizingEverythingOrHoldingBlocksConstant) {
  Batch batch = make_batch(15);
  // Every block leaves: nothing is kept, the prior is empty (and not a valid factor).
  std::vector<double*> all = batch.leaving();
  for (int k = 1; k < Batch::kKeyframes; ++k) {
    all.push_back(batch.pose[k].data());
    all.push_back(batch.speed_bias[k].data());
  }
  all.push_back(batch.extrinsic.data());
  for (auto& l : batch.lambda) all.push_back(l.data());
  const MarginalizationPrior none = marginalizer_for(batch, all).marginalize();
  EXPECT_TRUE(none.empty());
  EXPECT_TRUE(none.blocks.empty());
  EXPECT_THROW(MarginalizationFactor(std::make_shared<MarginalizationPrior>(none)), Error);

  // A constant extrinsic is not part of the prior.
  Marginalizer marginalizer = marginalizer_for(batch, batch.leaving());
  marginalizer.set_constant(batch.extrinsic.data());
  const MarginalizationPrior prior = marginalizer.marginalize();
  EXPECT_EQ(prior.index_of(batch.extrinsic.data()), -1);
  EXPECT_EQ(prior.tangent_size(), 21);
  EXPECT_TRUE(prior.J.allFinite());
}

// ---------------------------------------------------------------------------------------------
// The prior factor on the manifold.

TEST(Marginalization, BlockMinusInvertsThePoseManifoldPlus) {
  std::mt19937_64 rng(31);
  const PoseManifold manifold;
  for (int trial = 0; trial < 200; ++trial) {
    double x0[kPoseSize], x[kPoseSize], back[kPoseSize];
    pose_to_block(random_pose(rng), x0);
    // Tangent steps up to |d| = 1.5 (rotations up to 3 rad), and tiny ones (series branch).
    Eigen::Matrix<double, 6, 1> delta;
    delta << random_vector(rng, 1.0), random_vector(rng, trial % 4 == 0 ? 1e-9 : 1.5);
    if (delta.tail<3>().norm() > 1.5) delta.tail<3>() *= 1.5 / delta.tail<3>().norm();
    ASSERT_TRUE(manifold.Plus(x0, delta.data(), x));
    Eigen::Matrix<double, 6, 1> d;
    block_minus(BlockKind::kPose, kPoseSize, x, x0, d.data());
    EXPECT_LT((d - delta).norm(), 1e-12 * std::max(1.0, delta.norm()));
    // Invariant to the stored quaternion's sign and scale (both are the same rotation).
    for (int i = 3; i < kPoseSize; ++i) x[i] *= -2.5;
    Eigen::Matrix<double, 6, 1> d_flipped;
    block_minus(BlockKind::kPose, kPoseSize, x, x0, d_flipped.data());
    EXPECT_LT((d_flipped - delta).norm(), 1e-12 * std::max(1.0, delta.norm()));
    ASSERT_TRUE(manifold.Plus(x0, d.data(), back));
    EXPECT_LT(pose_from_block(back).q.angularDistance(pose_from_block(x).q), 1e-12);
  }
  Eigen::Matrix<double, 6, 1> zero;
  double x0[kPoseSize];
  pose_to_block(random_pose(rng), x0);
  block_minus(BlockKind::kPose, kPoseSize, x0, x0, zero.data());
  EXPECT_EQ(zero.norm(), 0.0);
}

TEST(Marginalization, FactorJacobiansMatchNumericDifferentiationOnTheManifold) {
  Batch batch = make_batch(16);
  auto prior = std::make_shared<const MarginalizationPrior>(marginalizer_for(batch, batch.leaving()).marginalize());
  const MarginalizationFactor factor(prior);
  ASSERT_EQ(factor.num_residuals(), prior->J.rows());
  const PoseManifold manifold;
  std::vector<const ceres::Manifold*> manifolds;
  for (BlockKind kind : prior->kinds) manifolds.push_back(kind == BlockKind::kPose ? &manifold : nullptr);

  // At x0 the residual is r and the tangent Jacobian J itself.
  Eigen::VectorXd residual(factor.num_residuals());
  ASSERT_TRUE(factor.Evaluate(prior->blocks.data(), residual.data(), nullptr));
  EXPECT_LT((residual - prior->r).norm(), 1e-12 * std::max(1.0, prior->r.norm()));
  EXPECT_TRUE(jacobians_match(factor, prior->blocks, manifolds, 1e-7));

  // Far from x0 (large rotations, a quaternion with w < 0 and not unit) the chain through
  // d(x [-] x0)/dx must still be exact.
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<std::vector<double>> moved(prior->blocks.size());
    std::vector<double*> blocks;
    for (std::size_t i = 0; i < prior->blocks.size(); ++i) {
      moved[i] = prior->x0[i];
      if (prior->kinds[i] == BlockKind::kPose) {
        SE3 T = pose_from_block(moved[i].data());
        const Vec3 dt = random_vector(rng, 0.5);  // drawn last argument first: the order of record (random_draws.hpp)
        pose_to_block(SE3(random_rotation(rng, 2.5) * T.q, T.t + dt), moved[i].data());
        if (trial % 2 == 1) {
          for (int k = 3; k < kPoseSize; ++k) moved[i][k] *= -1.3;
        }
      } else {
        for (double& v : moved[i]) v += 0.1 * random_vector(rng, 1.0).x();
      }
      blocks.push_back(moved[i].data());
    }
    EXPECT_TRUE(jacobians_match(factor, blocks, manifolds, 1e-7)) << "trial " << trial;
  }
}

TEST(Marginalization, RemapMovesBlockAddresses) {
  Batch batch = make_batch(18);
  auto prior = std::make_shared<MarginalizationPrior>(marginalizer_for(batch, batch.leaving()).marginalize());
  const MarginalizationFactor factor(prior);
  // Disturb the states so the residual is not just r.
  for (double& v : batch.speed_bias[1]) v += 0.01;
  batch.pose[2][0] += 0.05;
  Eigen::VectorXd before(factor.num_residuals());
  ASSERT_TRUE(factor.Evaluate(prior->blocks.data(), before.data(), nullptr));

  // The window rotates its arrays: keyframe k+1's states move to slot k; the extrinsic stays.
  Batch shifted = batch;
  std::unordered_map<const double*, double*> old_to_new;
  for (int k = 0; k + 1 < Batch::kKeyframes; ++k) {
    old_to_new[batch.pose[k + 1].data()] = shifted.pose[k].data();
    old_to_new[batch.speed_bias[k + 1].data()] = shifted.speed_bias[k].data();
    shifted.pose[k] = batch.pose[k + 1];
    shifted.speed_bias[k] = batch.speed_bias[k + 1];
  }
  std::vector<int> index_before;
  for (const auto& [from, to] : old_to_new) index_before.push_back(prior->index_of(from));
  const int extrinsic_index = prior->index_of(batch.extrinsic.data());
  ASSERT_NE(extrinsic_index, -1);
  prior->remap(old_to_new);
  std::size_t i = 0;
  for (const auto& [from, to] : old_to_new) {
    EXPECT_EQ(prior->index_of(to), index_before[i++]);
    EXPECT_EQ(prior->index_of(from), -1);
  }
  EXPECT_EQ(prior->index_of(batch.extrinsic.data()), extrinsic_index);  // unmapped: unchanged

  // Evaluated on the new memory, through a Problem, it gives the same residual.
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(options);
  MarginalizationFactor moved_factor(prior);
  problem.AddResidualBlock(&moved_factor, nullptr, prior->blocks);
  double cost = 0.0;
  std::vector<double> after;
  ASSERT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, &after, nullptr, nullptr));
  ASSERT_EQ(after.size(), static_cast<std::size_t>(before.size()));
  EXPECT_LT((Eigen::Map<Eigen::VectorXd>(after.data(), before.size()) - before).norm(), 1e-14 * before.norm());

  // Two blocks onto one address is an error.
  std::unordered_map<const double*, double*> clash{{prior->blocks[0], prior->blocks[1]}};
  EXPECT_THROW(prior->remap(clash), Error);
}

TEST(Marginalization, BorrowedFactorsStayWithTheirOwner) {
  // A factor owned elsewhere (e.g. by a ceres::Problem) enters a term without a second owner.
  std::vector<double> x{1.0, 2.0}, y{3.0};
  const LinearCost cost({Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Ones(2, 1)}, Eigen::VectorXd::Zero(2));
  const std::shared_ptr<const ceres::CostFunction> borrowed = borrow<ceres::CostFunction>(&cost);
  EXPECT_EQ(borrowed.get(), &cost);
  EXPECT_EQ(borrowed.use_count(), 0);  // no control block: nothing will delete it
  Marginalizer marginalizer;
  marginalizer.add({borrowed, nullptr, {x.data(), y.data()}, {0}});
  const MarginalizationPrior prior = marginalizer.marginalize();
  ASSERT_EQ(prior.blocks, std::vector<double*>{y.data()});
  // r = x + y: eliminating x leaves no information on y.
  EXPECT_TRUE(prior.empty());
}

TEST(Marginalization, BadInputIsRejected) {
  std::vector<double> x{1.0, 2.0}, y{3.0};
  const auto cost = std::make_shared<LinearCost>(std::vector<Eigen::MatrixXd>{Eigen::MatrixXd::Identity(2, 2)},
                                                 Eigen::VectorXd::Zero(2));
  Marginalizer m;
  EXPECT_THROW(m.add({nullptr, nullptr, {x.data()}, {0}}), Error);
  EXPECT_THROW(m.add({cost, nullptr, {x.data(), y.data()}, {0}}), Error);  // block count
  EXPECT_THROW(m.add({cost, nullptr, {nullptr}, {0}}), Error);
  EXPECT_THROW(m.add({cost, nullptr, {x.data()}, {1}}), Error);  // index out of range
  EXPECT_EQ(m.num_terms(), 0u);

  Marginalizer pose_of_wrong_size;
  pose_of_wrong_size.set_manifold(x.data(), BlockKind::kPose);
  pose_of_wrong_size.add({cost, nullptr, {x.data()}, {0}});
  EXPECT_THROW(pose_of_wrong_size.marginalize(), Error);

  Marginalizer constant_marginalized;
  constant_marginalized.set_constant(x.data());
  constant_marginalized.add({cost, nullptr, {x.data()}, {0}});
  EXPECT_THROW(constant_marginalized.marginalize(), Error);

  // A factor that cannot be evaluated (the point behind the target camera).
  double anchor[kPoseSize], target[kPoseSize], extrinsic[kPoseSize], lambda[1] = {0.5};
  pose_to_block(SE3(), anchor);
  pose_to_block(SE3(Quat::Identity(), Vec3(0.0, 0.0, 5.0)), target);
  pose_to_block(SE3(), extrinsic);
  Marginalizer failing;
  for (double* p : {anchor, target, extrinsic}) failing.set_manifold(p, BlockKind::kPose);
  failing.add({std::make_shared<ReprojectionFactor>(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), kMarginalFocal, kMarginalSigmaPx),
               nullptr, {anchor, target, extrinsic, lambda}, {0}});
  EXPECT_THROW(failing.marginalize(), Error);

  EXPECT_THROW(MarginalizationFactor(nullptr), Error);
  EXPECT_THROW(Marginalizer(Marginalizer::Options{-1.0, 0.0}), Error);
}

}  // namespace
}  // namespace navaid::estimation
