// The walking model of the Smart Cane's walking-path generator against closed forms: the LIPM
// solution (eq. 3-4) against a numerical integration of eq. 2, LFPC foot placement (eq. 7) against
// the paper's four printed lines, the stability interval of eq. 8 and the gait it settles to.
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/planning/lipm.hpp"

namespace navaid::planning {
namespace {

constexpr double kPi = 3.14159265358979323846;

// RK4 on r'' = (g / h) r, independent of the closed form.
LipmState integrate(const LipmParams& p, LipmState s, double t, int steps) {
  const double k = p.gravity / p.com_height_m;
  const double dt = t / steps;
  for (int i = 0; i < steps; ++i) {
    const auto f = [&](const Vec2& r, const Vec2& v) { return std::make_pair(v, Vec2(k * r)); };
    const auto [a1, b1] = f(s.r, s.v);
    const auto [a2, b2] = f(s.r + 0.5 * dt * a1, s.v + 0.5 * dt * b1);
    const auto [a3, b3] = f(s.r + 0.5 * dt * a2, s.v + 0.5 * dt * b2);
    const auto [a4, b4] = f(s.r + dt * a3, s.v + dt * b3);
    s.r += dt / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    s.v += dt / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4);
  }
  return s;
}

TEST(Lipm, ClosedFormSolvesEquation2OnBothAxes) {
  const LipmParams p;  // g = 10, h = 1, t_sup = 0.3
  const LipmState s0{Vec2(-0.27, 0.08), Vec2(1.9, -0.3)};
  for (const double t : {0.05, 0.15, 0.3, 0.6}) {
    const LipmState closed = lipm_propagate(p, s0, t);
    const LipmState numeric = integrate(p, s0, t, 2000);
    EXPECT_NEAR(closed.r.x(), numeric.r.x(), 1e-10) << t;
    EXPECT_NEAR(closed.r.y(), numeric.r.y(), 1e-10) << t;
    EXPECT_NEAR(closed.v.x(), numeric.v.x(), 1e-9) << t;
    EXPECT_NEAR(closed.v.y(), numeric.v.y(), 1e-9) << t;
  }
}

TEST(Lipm, Equation3KnownValuesWithTheVelocitysOneOverTc) {
  const LipmParams p;
  EXPECT_NEAR(p.time_constant(), std::sqrt(0.1), 1e-15);
  // x(0) = 0.1 m, v(0) = 0.5 m/s, t = 0.3 s, T_c = 0.316228 s: t / T_c = 0.948683.
  const double c = std::cosh(0.948683298050514);
  const double s = std::sinh(0.948683298050514);
  const LipmState out = lipm_propagate(p, LipmState{Vec2(0.1, 0.0), Vec2(0.5, 0.0)}, 0.3);
  EXPECT_NEAR(out.r.x(), 0.1 * c + 0.316227766016838 * 0.5 * s, 1e-12);
  EXPECT_NEAR(out.v.x(), 0.1 * s / 0.316227766016838 + 0.5 * c, 1e-12);
  EXPECT_NEAR(out.r.x(), 0.32201, 1e-5);  // 0.1 x 1.48478 + 0.316228 x 0.5 x 1.09753
  EXPECT_NEAR(out.v.x(), 1.08946, 1e-5);  // 0.1 x 1.09753 / 0.316228 + 0.5 x 1.48478
}

TEST(Lfpc, Equation7AsPrinted) {
  const double b = 0.4;
  const Vec2 v(1.2, -0.1);
  for (const double theta_deg : {0.0, 30.0, 90.0, -45.0, 170.0}) {
    const double th = theta_deg * kPi / 180.0;
    const LfpcInput u{0.5, 0.15, th};
    const double a_l = u.step_length_m;
    const double a_w = u.step_width_m;
    const Vec2 right = lfpc_foot_offset(u, Foot::kRight, b, v);
    const Vec2 left = lfpc_foot_offset(u, Foot::kLeft, b, v);
    EXPECT_NEAR(right.x(), -a_l * std::cos(th) + a_w * std::sin(th) + b * v.x(), 1e-12) << theta_deg;
    EXPECT_NEAR(right.y(), -a_l * std::sin(th) - a_w * std::cos(th) + b * v.y(), 1e-12) << theta_deg;
    EXPECT_NEAR(left.x(), -a_l * std::cos(th) - a_w * std::sin(th) + b * v.x(), 1e-12) << theta_deg;
    EXPECT_NEAR(left.y(), -a_l * std::sin(th) + a_w * std::cos(th) + b * v.y(), 1e-12) << theta_deg;
  }
  // theta = 0, at rest: eq. 6 (the right foot a_w to the right, the left to the left).
  const Vec2 r0 = lfpc_foot_offset(LfpcInput{0.5, 0.15, 0.0}, Foot::kRight, b, Vec2::Zero());
  EXPECT_NEAR(r0.x(), -0.5, 1e-15);
  EXPECT_NEAR(r0.y(), -0.15, 1e-15);
}

TEST(Lfpc, Equation8StableGainsWithThePapersParameters) {
  const LipmParams p;
  const GainInterval g = lfpc_stable_gains(p);
  const double tc = std::sqrt(0.1);
  const double c = std::cosh(0.3 / tc);
  const double s = std::sinh(0.3 / tc);
  EXPECT_NEAR(g.low, tc * (c - 1.0) / s, 1e-15);
  EXPECT_NEAR(g.high, tc * (c + 1.0) / s, 1e-15);
  EXPECT_NEAR(g.low, 0.13968, 1e-5);
  EXPECT_NEAR(g.high, 0.71593, 1e-5);
  EXPECT_TRUE(g.contains(0.4));  // the paper's b
  EXPECT_FALSE(g.contains(0.1));
  EXPECT_FALSE(g.contains(0.8));
}

// Walks straight with one input for n steps from rest; returns the touchdown speeds.
std::vector<double> speeds(double b, int n) {
  const LipmParams p;
  const LipmStepTable table = lipm_step_table(p, 3);
  WalkerState s;
  std::vector<double> out;
  for (int i = 0; i < n; ++i) {
    s = lfpc_step(table, b, s, LfpcInput{0.5, 0.15, 0.0});
    out.push_back(s.velocity.x());
  }
  return out;
}

TEST(Lfpc, InsideEquation8TheGaitSettlesToTheSteadySpeed) {
  const LipmParams p;
  const double v_star = lfpc_steady_speed(p, 0.5, 0.4);
  const double tc = std::sqrt(0.1);
  const double k = std::sinh(0.3 / tc) / tc;
  EXPECT_NEAR(v_star, k * 0.5 / (1.0 - std::cosh(0.3 / tc) + 0.4 * k), 1e-12);
  EXPECT_NEAR(v_star, 1.92070, 1e-5);
  const std::vector<double> v = speeds(0.4, 40);
  EXPECT_NEAR(v.back(), v_star, 1e-6);
  // The velocity map's slope is c - b s / T_c = 1.48478 - 0.4 x 3.47068 = 0.0965: the error shrinks
  // by about ten each step.
  EXPECT_NEAR((v[3] - v_star) / (v[2] - v_star), std::cosh(0.3 / tc) - 0.4 * k, 1e-9);
}

TEST(Lfpc, OutsideEquation8TheGaitDiverges) {
  const std::vector<double> low = speeds(0.1, 30);    // slope 1.48 - 0.35 = 1.14 > 1: runs away
  const std::vector<double> high = speeds(0.8, 30);   // slope 1.48 - 2.78 = -1.29 < -1: oscillates away
  EXPECT_GT(std::abs(low.back()), 1e2);
  EXPECT_GT(std::abs(high.back()), 1e2);
  EXPECT_LT(high[10] * high[11], 0.0);  // the sign alternates
}

TEST(Lfpc, StepsAlternateFeetAndTheTableMatchesTheClosedForm) {
  const LipmParams p;
  const LipmStepTable table = lipm_step_table(p, 4);
  WalkerState s;
  s.velocity = Vec2(1.5, 0.1);
  s.com = Vec2(2.0, 3.0);
  std::vector<Vec2> samples;
  const LfpcInput u{0.55, 0.12, 0.3};
  const WalkerState n = lfpc_step(table, 0.4, s, u, &samples);
  const Vec2 foot = s.com + lfpc_foot_offset(u, Foot::kRight, 0.4, s.velocity);
  EXPECT_TRUE(n.support_foot.isApprox(foot, 1e-12));
  EXPECT_EQ(n.next, Foot::kLeft);
  EXPECT_DOUBLE_EQ(n.direction_rad, 0.3);
  ASSERT_EQ(samples.size(), 4U);
  for (int i = 1; i <= 4; ++i) {
    const LipmState c = lipm_propagate(p, LipmState{s.com - foot, s.velocity}, 0.3 * i / 4.0);
    EXPECT_TRUE(samples[static_cast<std::size_t>(i - 1)].isApprox(foot + c.r, 1e-12)) << i;
  }
  EXPECT_TRUE(n.com.isApprox(samples.back(), 1e-12));
  const LipmState end = lipm_propagate(p, LipmState{s.com - foot, s.velocity}, 0.3);
  EXPECT_TRUE(n.velocity.isApprox(end.v, 1e-12));
}

TEST(Lfpc, TurningInputsTurnTheWalk) {
  // Thirty-degree turns every step: the CoM velocity follows the walking direction around.
  const LipmParams p;
  const LipmStepTable table = lipm_step_table(p, 3);
  WalkerState s;
  s.velocity = Vec2(lfpc_steady_speed(p, 0.5, 0.4), 0.0);
  double theta = 0.0;
  for (int i = 0; i < 6; ++i) {
    theta += kPi / 6.0;
    s = lfpc_step(table, 0.4, s, LfpcInput{0.5, 0.15, theta});
  }
  // After six turns of 30 deg the walker heads back: its velocity points to -x.
  EXPECT_LT(s.velocity.x(), 0.0);
}

}  // namespace
}  // namespace navaid::planning
