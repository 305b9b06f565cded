// Reprojection and depth-3D factors with the camera-IMU time offset td as a parameter block.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "factor_check.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/estimation/factors/depth_3d_factor.hpp"
#include "navaid/estimation/factors/inverse_depth_factor.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"
#include "navaid/estimation/factors/reprojection_factor.hpp"
#include "navaid/estimation/factors/time_offset_factors.hpp"

namespace navaid::estimation {
namespace {

using testing::jacobians_match;
using testing::random_pose;
using testing::random_rotation;
using testing::random_vector;

constexpr double kFocal = 525.0;
constexpr double kSigmaPx = 1.5;
const double kSigmaLambda = inverse_depth_sigma(0.2, kFocal, 0.075);

// The parameter blocks of one feature seen from two keyframes, plus td.
struct Blocks {
  double anchor[kPoseSize], target[kPoseSize], extrinsic[kPoseSize];
  double lambda[1] = {0.3};
  double td[1] = {0.0};
  std::vector<double*> all() { return {anchor, target, extrinsic, lambda, td}; }
};

// A body moving with constant body-frame angular velocity w and world velocity u:
// T_W_B(t) = (R0 Exp(w t), p0 + u t).
struct ScrewMotion {
  SE3 T_W_B0;
  Vec3 w, u;
  SE3 T_W_B(double t) const { return SE3(T_W_B0.q * so3_exp(w * t), T_W_B0.t + u * t); }
};

Eigen::Vector2d project(const Vec3& P_c) { return P_c.head<2>() / P_c.z(); }

// Where a world point appears (normalized plane) at time t, its depth, and their rates there.
struct Seen {
  Eigen::Vector2d m, velocity;
  double z, z_rate;
};
Seen observe(const ScrewMotion& motion, const SE3& T_B_C, const Vec3& p_W, double t) {
  auto at = [&](double s) { return (motion.T_W_B(s) * T_B_C).inverse() * p_W; };
  const double h = 1e-6;  // [s] central difference: error ~ h^2, far below what the tests resolve
  const Vec3 P = at(t);
  return {project(P), (project(at(t + h)) - project(at(t - h))) / (2.0 * h), P.z(),
          (at(t + h).z() - at(t - h).z()) / (2.0 * h)};
}

// Random keyframe blocks and timed observations (not consistent with each other: for Jacobians).
struct RandomCase {
  Blocks b;
  TimedObservation anchor, target;
  double depth, depth_rate;
};

RandomCase random_case(std::mt19937_64& rng) {
  RandomCase c;
  const SE3 T_W_Ba = random_pose(rng);
  // Drawn last argument first: the order of record (random_draws.hpp).
  const Vec3 t_B_C = random_vector(rng, 0.1);
  const SE3 T_B_C(random_rotation(rng), t_B_C);
  const Vec3 t_Ca_Ct = random_vector(rng, 0.4);
  const SE3 T_Ca_Ct(random_rotation(rng, 0.3), t_Ca_Ct);
  pose_to_block(T_W_Ba, c.b.anchor);
  pose_to_block(T_W_Ba * T_B_C * T_Ca_Ct * T_B_C.inverse(), c.b.target);
  pose_to_block(T_B_C, c.b.extrinsic);
  std::uniform_real_distribution<double> xy(-0.3, 0.3), speed(-1.0, 1.0), td(-0.02, 0.02), depth(1.0, 5.0);
  c.b.lambda[0] = 1.0 / depth(rng);
  c.b.td[0] = td(rng);
  for (TimedObservation* o : {&c.anchor, &c.target}) {
    o->m = draw_vector<2>([&] { return xy(rng); });
    o->velocity = draw_vector<2>([&] { return speed(rng); });
    o->td0_s = td(rng);
  }
  c.depth = depth(rng);
  c.depth_rate = speed(rng);
  return c;
}

TEST(TimeOffsetFactors, AnalyticJacobiansMatchNumericForEveryBlock) {
  std::mt19937_64 rng(31);
  const PoseManifold pm;
  const std::vector<const ceres::Manifold*> manifolds = {&pm, &pm, &pm, nullptr, nullptr};
  for (int trial = 0; trial < 20; ++trial) {
    RandomCase c = random_case(rng);
    const ReprojectionTdFactor reprojection(c.anchor, c.target, kFocal, kSigmaPx);
    const Depth3dTdFactor depth(c.anchor, c.target, c.depth, c.depth_rate, kFocal, kSigmaLambda);
    EXPECT_TRUE(jacobians_match(reprojection, c.b.all(), manifolds)) << "trial " << trial;
    EXPECT_TRUE(jacobians_match(depth, c.b.all(), manifolds)) << "trial " << trial;
  }
}

// A factor evaluated with every Jacobian (row-major, one vector per block).
struct Evaluated {
  Eigen::VectorXd r;
  std::vector<std::vector<double>> J;
  bool ok;
  Evaluated(const ceres::CostFunction& f, std::vector<double*> blocks) : r(f.num_residuals()) {
    std::vector<double*> J_ptrs;
    for (int size : f.parameter_block_sizes()) J.emplace_back(static_cast<std::size_t>(size * f.num_residuals()));
    for (auto& j : J) J_ptrs.push_back(j.data());
    ok = f.Evaluate(blocks.data(), r.data(), J_ptrs.data());
  }
};

TEST(TimeOffsetFactors, AtTheCorrectionOffsetTheyAreThePlainFactorsBitForBit) {
  std::mt19937_64 rng(32);
  for (int trial = 0; trial < 20; ++trial) {
    RandomCase c = random_case(rng);
    c.target.td0_s = c.anchor.td0_s;
    c.b.td[0] = c.anchor.td0_s;
    const Evaluated td_r(ReprojectionTdFactor(c.anchor, c.target, kFocal, kSigmaPx), c.b.all());
    const Evaluated plain_r(ReprojectionFactor(c.anchor.m, c.target.m, kFocal, kSigmaPx), c.b.all());
    const Evaluated td_d(Depth3dTdFactor(c.anchor, c.target, c.depth, c.depth_rate, kFocal, kSigmaLambda), c.b.all());
    const Evaluated plain_d(Depth3dFactor(c.anchor.m, c.target.m, c.depth, kFocal, kSigmaLambda), c.b.all());
    ASSERT_TRUE(td_r.ok && plain_r.ok && td_d.ok && plain_d.ok);
    EXPECT_EQ(td_r.r, plain_r.r);
    EXPECT_EQ(td_d.r, plain_d.r);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(td_r.J[k], plain_r.J[k]) << "block " << k;
      EXPECT_EQ(td_d.J[k], plain_d.J[k]) << "block " << k;
    }
    // Away from td0 the residual changes: the td block is not inert.
    c.b.td[0] += 0.01;
    const Evaluated moved(ReprojectionTdFactor(c.anchor, c.target, kFocal, kSigmaPx), c.b.all());
    EXPECT_GT((moved.r - plain_r.r).norm(), 1e-3);
  }
}

// Closed form. The anchor camera is still (v_a = 0); the target camera (= body) translates along
// its x axis at speed u, so a point at depth Z moves on the image at v = (-u/Z, 0), exactly
// linearly. The target observation was exposed at state time + (td_true - td0):
//   m_t = ((X - p_x - u (td_true - td0)) / Z, Y / Z)
// and with the states at the truth, r(td) = s (u (td_true - td) / Z, 0) for the reprojection
// factor and S_x (-u (td_true - td), 0, 0) for the 3D factor (s = f / sigma, S_x = f / (Z sigma)).
TEST(TimeOffsetFactors, KnownAnswerForAShiftAlongTheImageRow) {
  const double u = 1.2, Z = 2.5, X = 0.4, Y = -0.3, p_x = 0.25;  // [m/s], [m]
  const double td_true = 0.015, td0 = 0.004;
  Blocks b;
  pose_to_block(SE3::identity(), b.anchor);
  pose_to_block(SE3(Quat::Identity(), Vec3(p_x, 0, 0)), b.target);
  pose_to_block(SE3::identity(), b.extrinsic);
  b.lambda[0] = 1.0 / Z;
  TimedObservation anchor{Eigen::Vector2d(X / Z, Y / Z), Eigen::Vector2d::Zero(), 0.0};
  TimedObservation target{Eigen::Vector2d((X - p_x - u * (td_true - td0)) / Z, Y / Z), Eigen::Vector2d(-u / Z, 0.0),
                          td0};
  const ReprojectionTdFactor reprojection(anchor, target, kFocal, kSigmaPx);
  const Depth3dTdFactor depth(anchor, target, Z, 0.0, kFocal, kSigmaLambda);
  const double s = kFocal / kSigmaPx, S_x = kFocal / (Z * kSigmaPx);
  for (double td : {td0, td_true, 0.0, -0.03, 0.05}) {
    b.td[0] = td;
    const Evaluated r(reprojection, b.all());
    const Evaluated d(depth, b.all());
    ASSERT_TRUE(r.ok && d.ok);
    EXPECT_NEAR(r.r.x(), s * u * (td_true - td) / Z, 1e-9) << "td " << td;
    EXPECT_NEAR(r.r.y(), 0.0, 1e-9);
    EXPECT_NEAR(d.r.x(), -S_x * u * (td_true - td), 1e-9) << "td " << td;
    EXPECT_NEAR(d.r.y(), 0.0, 1e-9);
    EXPECT_NEAR(d.r.z(), 0.0, 1e-9);
    EXPECT_NEAR(r.J[4][0], -s * u / Z, 1e-9);
    EXPECT_NEAR(r.J[4][1], 0.0, 1e-12);
    EXPECT_NEAR(d.J[4][0], S_x * u, 1e-9);
  }
}

// A walking-like camera (rotating and translating) with td_true = 12 ms and frames corrected with
// other td0: the measurements, image velocities and depth rates come from the motion at the
// exposure times, the states are the truth at the state times. Gauss-Newton on td alone must
// recover td_true up to the second-order image motion (1/2 a (td - td0)^2) the factors leave out.
// The keyframes are 0.5 s apart: td shows only where the two frames' image motions differ (a
// common shift is nearly a displacement of the point), so close frames constrain it weakly.
template <class Make>
void recovers_time_offset(Make make, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double td_true = 0.012;
  const double t_anchor = 0.0, t_target = 0.5;        // state times (IMU clock) [s]
  const double td0_anchor = 0.0, td0_target = 0.005;  // what each frame was corrected with
  const ScrewMotion motion{random_pose(rng), Vec3(0.3, -0.5, 0.4), Vec3(1.2, 0.2, -0.1)};
  const SE3 T_B_C(quat_from_rpy(-M_PI / 2, 0.0, -M_PI / 2), Vec3(0.05, 0.0, 0.02));  // camera looks along body x
  std::uniform_real_distribution<double> xy(-0.4, 0.4), depth(1.5, 6.0);

  struct Feature {
    std::unique_ptr<ceres::CostFunction> f;
    Blocks b;
  };
  std::vector<Feature> features;
  while (features.size() < 30) {
    const double z = depth(rng);
    const SE3 T_W_Ca = motion.T_W_B(t_anchor) * T_B_C;
    const double y = xy(rng) * z;  // y before x: the order of record (random_draws.hpp)
    const Vec3 p_W = T_W_Ca * Vec3(xy(rng) * z, y, z);
    const Seen a = observe(motion, T_B_C, p_W, t_anchor + td_true - td0_anchor);
    const Seen t = observe(motion, T_B_C, p_W, t_target + td_true - td0_target);
    if (t.z < 0.5) continue;
    Feature feat;
    feat.f = make(TimedObservation{a.m, a.velocity, td0_anchor}, TimedObservation{t.m, t.velocity, td0_target}, t);
    pose_to_block(motion.T_W_B(t_anchor), feat.b.anchor);
    pose_to_block(motion.T_W_B(t_target), feat.b.target);
    pose_to_block(T_B_C, feat.b.extrinsic);
    feat.b.lambda[0] = 1.0 / z;
    features.push_back(std::move(feat));
  }

  auto cost = [&](double td) {
    double sum = 0;
    for (auto& feat : features) {
      feat.b.td[0] = td;
      sum += Evaluated(*feat.f, feat.b.all()).r.squaredNorm();
    }
    return sum;
  };
  double td = 0.0;
  const double cost_start = cost(td);
  for (int it = 0; it < 5; ++it) {
    double JtJ = 0, Jtr = 0;
    for (auto& feat : features) {
      feat.b.td[0] = td;
      const Evaluated e(*feat.f, feat.b.all());
      ASSERT_TRUE(e.ok);
      for (int k = 0; k < e.r.size(); ++k) {
        JtJ += e.J[4][k] * e.J[4][k];
        Jtr += e.J[4][k] * e.r[k];
      }
    }
    td -= Jtr / JtJ;
  }
  EXPECT_NEAR(td, td_true, 2e-4);  // measured: 0.07 ms (reprojection), 0.01 ms (3D)
  EXPECT_LT(cost(td), 1e-3 * cost_start) << "start " << cost_start;
}

TEST(TimeOffsetFactors, GaussNewtonOnTdRecoversTheTrueOffsetOfAMovingCamera) {
  recovers_time_offset(
      [](const TimedObservation& a, const TimedObservation& t, const Seen&) -> std::unique_ptr<ceres::CostFunction> {
        return std::make_unique<ReprojectionTdFactor>(a, t, kFocal, kSigmaPx);
      },
      41);
  recovers_time_offset(
      [](const TimedObservation& a, const TimedObservation& t, const Seen& seen) -> std::unique_ptr<ceres::CostFunction> {
        return std::make_unique<Depth3dTdFactor>(a, t, seen.z, seen.z_rate, kFocal, kSigmaLambda);
      },
      42);
}

TEST(TimeOffsetFactors, RejectBadInput) {
  const TimedObservation ok{Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(0.5, 0.0), 0.0};
  TimedObservation bad_v = ok;
  bad_v.velocity.x() = std::numeric_limits<double>::quiet_NaN();
  TimedObservation bad_td0 = ok;
  bad_td0.td0_s = std::numeric_limits<double>::infinity();
  EXPECT_THROW(ReprojectionTdFactor(ok, bad_v, kFocal, kSigmaPx), Error);
  EXPECT_THROW(ReprojectionTdFactor(bad_td0, ok, kFocal, kSigmaPx), Error);
  EXPECT_THROW(ReprojectionTdFactor(ok, ok, 0.0, kSigmaPx), ConfigError);
  EXPECT_THROW(Depth3dTdFactor(ok, bad_v, 2.0, 0.0, kFocal, kSigmaLambda), Error);
  EXPECT_THROW(Depth3dTdFactor(ok, ok, 2.0, std::numeric_limits<double>::quiet_NaN(), kFocal, kSigmaLambda), Error);
  EXPECT_THROW(Depth3dTdFactor(ok, ok, 0.0, 0.0, kFocal, kSigmaLambda), Error);
  EXPECT_THROW(Depth3dTdFactor(ok, ok, 2.0, 0.0, kFocal, 0.0), ConfigError);
}

}  // namespace
}  // namespace navaid::estimation
