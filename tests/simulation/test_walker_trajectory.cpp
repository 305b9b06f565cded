#include "navaid/simulation/walker_trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {
namespace {

std::vector<Eigen::Vector2d> zigzag() {
  return {{0.0, 0.0}, {10.0, 0.0}, {10.0, 8.0}, {3.0, 12.0}, {-2.0, 5.0}};
}

double polyline_length(const std::vector<Eigen::Vector2d>& w) {
  double len = 0.0;
  for (std::size_t i = 1; i < w.size(); ++i) len += (w[i] - w[i - 1]).norm();
  return len;
}

double distance_to_polyline(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& w) {
  double best = 1e300;
  for (std::size_t i = 1; i < w.size(); ++i) {
    const Eigen::Vector2d d = w[i] - w[i - 1];
    const double a = std::clamp((p - w[i - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (w[i - 1] + a * d)).norm());
  }
  return best;
}

WalkerConfig no_gait() {
  WalkerConfig c;
  c.bob_amplitude_m = c.sway_amplitude_m = c.pitch_amplitude_rad = c.roll_amplitude_rad = 0.0;
  c.scan_amplitude_rad = 0.0;
  return c;
}

TEST(WalkerTrajectory, AnalyticDerivativesMatchNumeric) {
  const WalkerTrajectory traj(zigzag());
  const double h = 1e-5;
  int checked = 0;
  for (double t = -0.5; t < traj.duration() + 0.5; t += 0.0731) {
    const KinematicState s = traj.state(t);
    const KinematicState sm = traj.state(t - h), sp = traj.state(t + h);
    const Vec3 v_num = (sp.T_W_B.t - sm.T_W_B.t) / (2 * h);
    const Vec3 a_num = (sp.v_W - sm.v_W) / (2 * h);
    const double h2 = 1e-3;  // second difference: larger step against roundoff (~1e-13 / h2^2)
    const Vec3 a_num2 = (traj.state(t + h2).T_W_B.t - 2.0 * s.T_W_B.t + traj.state(t - h2).T_W_B.t) / (h2 * h2);
    const Vec3 w_num = so3_log(sm.T_W_B.q.conjugate() * sp.T_W_B.q) / (2 * h);
    const Vec3 al_num = (sp.omega_B - sm.omega_B) / (2 * h);
    EXPECT_LT((s.v_W - v_num).norm(), 1e-6) << "t=" << t;
    EXPECT_LT((s.a_W - a_num).norm(), 1e-5) << "t=" << t;
    EXPECT_LT((s.a_W - a_num2).norm(), 1e-3) << "t=" << t;
    EXPECT_LT((s.omega_B - w_num).norm(), 1e-6) << "t=" << t;
    EXPECT_LT((s.alpha_B - al_num).norm(), 1e-5) << "t=" << t;
    ++checked;
  }
  EXPECT_GT(checked, 400);
}

TEST(WalkerTrajectory, FollowsPathAtConstantSpeed) {
  const auto w = zigzag();
  for (const bool gait : {false, true}) {
    const WalkerConfig cfg = gait ? WalkerConfig{} : no_gait();
    const WalkerTrajectory traj(w, cfg);
    const double poly = polyline_length(w);
    // Corners are cut by a few cm only; three corners.
    EXPECT_LT(traj.length(), poly);
    EXPECT_GT(traj.length(), poly - 3 * 0.2);
    EXPECT_NEAR(traj.duration(), traj.length() / cfg.speed_mps + cfg.ramp_time_s, 1e-12);

    // Uniform quintic B-spline cuts a corner by at most 56/120 spacing; gait adds the sway.
    const double bound = 56.0 / 120.0 * cfg.corner_spacing_m + cfg.sway_amplitude_m + 1e-9;
    double max_dev = 0.0;
    for (double t = 0.0; t <= traj.duration(); t += 0.01) {
      const KinematicState s = traj.state(t);
      max_dev = std::max(max_dev, distance_to_polyline(s.T_W_B.t.head<2>(), w));
      EXPECT_NEAR(s.T_W_B.t.z(), cfg.ground_z_m + cfg.mount_height_m, cfg.bob_amplitude_m + 1e-12);
      if (t > cfg.ramp_time_s && t < traj.duration() - cfg.ramp_time_s) {
        // Without gait the speed is exact; with gait the lateral sway velocity (<= pi f A_sway
        // plus a curvature term) and the vertical bob velocity (<= 2 pi f A_bob) are added.
        EXPECT_NEAR(s.v_W.head<2>().norm(), cfg.speed_mps, gait ? 0.2 : 1e-7) << "t=" << t;
        EXPECT_LE(std::abs(s.v_W.z()), 2 * M_PI * cfg.step_frequency_hz * cfg.bob_amplitude_m + 1e-12);
      }
    }
    EXPECT_LT(max_dev, bound);
    EXPECT_GT(max_dev, 0.05);  // corners really are rounded

    // Exact start/end points, at rest outside [0, duration].
    EXPECT_LT((traj.state(0.0).T_W_B.t.head<2>() - w.front()).norm(), 1e-9);
    EXPECT_LT((traj.state(traj.duration()).T_W_B.t.head<2>() - w.back()).norm(), 1e-9);
    for (const double t : {-1.0, 0.0, traj.duration(), traj.duration() + 2.0}) {
      EXPECT_LT(traj.state(t).v_W.norm(), 1e-12);
      EXPECT_LT(traj.state(t).a_W.norm(), 1e-12);
    }
  }
}

TEST(WalkerTrajectory, HeadingFollowsTangentAndStraightLineIsExact) {
  const std::vector<Eigen::Vector2d> line = {{1.0, 2.0}, {1.0 + 30.0 * std::cos(0.4), 2.0 + 30.0 * std::sin(0.4)}};
  const WalkerTrajectory traj(line, no_gait());
  EXPECT_NEAR(traj.length(), 30.0, 1e-9);
  for (double t = 0.0; t <= traj.duration(); t += 0.37) {
    const KinematicState s = traj.state(t);
    EXPECT_LT(distance_to_polyline(s.T_W_B.t.head<2>(), line), 1e-9);
    EXPECT_NEAR(yaw_of(s.T_W_B.q), 0.4, 1e-9);  // body x points along the path
    EXPECT_LT(s.omega_B.norm(), 1e-9);
  }
  // Forward velocity is along body +x (x forward, y left, z up).
  const KinematicState mid = traj.state(0.5 * traj.duration());
  const Vec3 v_B = mid.T_W_B.q.conjugate() * mid.v_W;
  EXPECT_NEAR(v_B.x(), 1.1, 1e-9);
  EXPECT_NEAR(v_B.y(), 0.0, 1e-9);
}

TEST(WalkerTrajectory, LeftTurnHasPositiveYawRate) {
  const WalkerTrajectory traj({{0, 0}, {5, 0}, {5, 5}}, no_gait());
  double max_rate = 0.0;
  for (double t = 0.0; t <= traj.duration(); t += 0.01) max_rate = std::max(max_rate, traj.state(t).omega_B.z());
  EXPECT_GT(max_rate, 0.5);
  EXPECT_NEAR(yaw_of(traj.state(traj.duration()).T_W_B.q), M_PI / 2, 1e-9);
}

TEST(WalkerTrajectory, ShortPathShrinksRampsAndBadInputThrows) {
  const WalkerTrajectory traj({{0, 0}, {0.3, 0}});
  EXPECT_NEAR(traj.length(), 0.3, 1e-12);
  EXPECT_NEAR(traj.state(traj.duration()).T_W_B.t.x(), 0.3, 1e-9);
  EXPECT_THROW(WalkerTrajectory({{0, 0}}), ConfigError);
  EXPECT_THROW(WalkerTrajectory({{0, 0}, {0, 0}}), ConfigError);
  WalkerConfig bad;
  bad.speed_mps = 0.0;
  EXPECT_THROW(WalkerTrajectory({{0, 0}, {1, 0}}, bad), ConfigError);
}

}  // namespace
}  // namespace navaid::simulation
