#include "navaid/simulation/magnetometer_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"

namespace navaid::simulation {
namespace {


SE3 yaw_pose(double yaw, const Vec3& t) { return SE3(quat_from_rpy(0.0, 0.0, yaw), t); }

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

MagnetometerModelConfig noiseless() {
  MagnetometerModelConfig c;
  c.noise = false;
  return c;
}

TEST(MagnetometerModel, NoiselessNormIsPreserved) {
  MagnetometerModel m(noiseless());
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  const double norm = m.config().field_enu_t.norm();
  for (int k = 0; k < 100; ++k) {
    const SE3 T_ENU_W = yaw_pose(angle(rng), Vec3(1.0, 2.0, 3.0));
    const Vec3 rpy = draw_vector<3>([&] { return angle(rng); });
    const SE3 T_W_B(quat_from_rpy(0.5 * rpy.x(), 0.5 * rpy.y(), rpy.z()), Vec3(4.0, 5.0, 6.0));
    const MagSample s = m.measure(k, T_ENU_W, T_W_B);
    EXPECT_EQ(s.t, k);
    EXPECT_NEAR(s.field.norm(), norm, 1e-15);
  }
}

TEST(MagnetometerModel, HeadingFromHorizontalFieldMatchesYaw) {
  MagnetometerModel m(noiseless());
  for (double yaw_enu_w : {0.0, 0.4, -1.2}) {
    for (double yaw_w_b : {0.0, 1.0, 2.5, -3.0, -0.3}) {
      const MagSample s = m.measure(0, yaw_pose(yaw_enu_w, Vec3::Zero()), yaw_pose(yaw_w_b, Vec3(1.0, 0.0, 0.0)));
      // Level body: north is at angle pi/2 - yaw from the body x axis, counter-clockwise.
      const double yaw = M_PI / 2.0 - std::atan2(s.field.y(), s.field.x());
      EXPECT_NEAR(wrap(yaw - (yaw_enu_w + yaw_w_b)), 0.0, 1e-12) << yaw_enu_w << " " << yaw_w_b;
      EXPECT_NEAR(s.field.z(), m.config().field_enu_t.z(), 1e-18);  // up stays up
    }
  }
  // Facing north (yaw pi/2), the field is straight ahead along x.
  const MagSample north = m.measure(0, SE3::identity(), yaw_pose(M_PI / 2.0, Vec3::Zero()));
  EXPECT_NEAR(north.field.x(), 20e-6, 1e-15);
  EXPECT_NEAR(north.field.y(), 0.0, 1e-15);
}

TEST(MagnetometerModel, HardAndSoftIronApplied) {
  MagnetometerModelConfig c = noiseless();
  MagnetometerModel ideal(c);
  Mat3 a;
  a << 1.10, 0.05, -0.02,  //
      0.05, 0.95, 0.03,    //
      -0.02, 0.03, 1.02;
  c.soft_iron = a;
  c.hard_iron_t = Vec3(12e-6, -30e-6, 5e-6);
  MagnetometerModel distorted(c);
  const SE3 T_ENU_W = yaw_pose(0.3, Vec3::Zero());
  const SE3 T_W_B(quat_from_rpy(0.1, -0.2, 1.3), Vec3::Zero());
  const Vec3 expected = a * ideal.measure(0, T_ENU_W, T_W_B).field + c.hard_iron_t;
  EXPECT_LT((distorted.measure(0, T_ENU_W, T_W_B).field - expected).norm(), 1e-18);
  // Explicit formula: A R_B_ENU m_ENU + b.
  const Mat3 R_B_ENU = (T_ENU_W.rotation() * T_W_B.rotation()).transpose();
  EXPECT_LT((distorted.expected_field_B(T_ENU_W, T_W_B) - (a * R_B_ENU * c.field_enu_t + c.hard_iron_t)).norm(),
            1e-18);
}

TEST(MagnetometerModel, NoiseMatchesSigma) {
  MagnetometerModelConfig c;
  c.sigma_t = 0.5e-6;
  c.seed = 9;
  MagnetometerModel m(c);
  const SE3 T_W_B(quat_from_rpy(0.2, 0.1, 0.7), Vec3::Zero());
  const Vec3 truth = m.expected_field_B(SE3::identity(), T_W_B);
  const int n = 20000;
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
  for (int k = 0; k < n; ++k) {
    const Vec3 e = m.measure(k, SE3::identity(), T_W_B).field - truth;
    sum += e;
    sum2 += e.cwiseAbs2();
  }
  const Vec3 mean = sum / n;
  const Vec3 sd = (sum2 / n - mean.cwiseAbs2()).cwiseSqrt();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sd[i], 0.5e-6, 0.5e-6 * 0.03) << i;     // SE 0.5%
    EXPECT_LT(std::abs(mean[i]), 5.0 * 0.5e-6 / std::sqrt(n)) << i;
  }
}

TEST(MagnetometerModel, DeterministicBySeed) {
  MagnetometerModelConfig c;
  c.seed = 4;
  MagnetometerModel a(c), b(c);
  c.seed = 5;
  MagnetometerModel other(c);
  const SE3 T_W_B(quat_from_rpy(0.0, 0.0, 0.5), Vec3::Zero());
  for (int k = 0; k < 20; ++k) {
    const Vec3 fa = a.measure(k, SE3::identity(), T_W_B).field;
    EXPECT_EQ(fa, b.measure(k, SE3::identity(), T_W_B).field);
    EXPECT_NE(fa, other.measure(k, SE3::identity(), T_W_B).field);
  }
}

TEST(MagnetometerModel, BadConfigNamesTheKey) {
  struct Case {
    std::function<void(MagnetometerModelConfig&)> mutate;
    std::string key;
  };
  Mat3 asymmetric = Mat3::Identity();
  asymmetric(0, 1) = 0.2;
  Mat3 indefinite = Mat3::Identity();
  indefinite(2, 2) = -1.0;
  Mat3 singular = Mat3::Identity();
  singular(1, 1) = 0.0;
  Mat3 nan = Mat3::Identity();
  nan(0, 2) = nan(2, 0) = std::nan("");
  const std::vector<Case> cases = {
      {[](MagnetometerModelConfig& c) { c.field_enu_t = Vec3(0.0, 20.0, -45.0); }, "field_enu_t"},  // uT as T
      {[](MagnetometerModelConfig& c) { c.field_enu_t = Vec3::Zero(); }, "field_enu_t"},
      {[](MagnetometerModelConfig& c) { c.hard_iron_t = Vec3(0.0, std::nan(""), 0.0); }, "hard_iron_t"},
      {[](MagnetometerModelConfig& c) { c.sigma_t = -1e-7; }, "sigma_t"},
      {[&](MagnetometerModelConfig& c) { c.soft_iron = asymmetric; }, "soft_iron"},
      {[&](MagnetometerModelConfig& c) { c.soft_iron = indefinite; }, "soft_iron"},
      {[&](MagnetometerModelConfig& c) { c.soft_iron = singular; }, "soft_iron"},
      {[&](MagnetometerModelConfig& c) { c.soft_iron = -Mat3::Identity(); }, "soft_iron"},
      {[&](MagnetometerModelConfig& c) { c.soft_iron = nan; }, "soft_iron"},
  };
  for (const auto& k : cases) {
    MagnetometerModelConfig c;
    k.mutate(c);
    try {
      MagnetometerModel m(c);
      ADD_FAILURE() << "no ConfigError for " << k.key;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.key(), k.key) << e.what();
    }
  }
  // Tiny asymmetry (numerical round-off of a calibration) is accepted.
  MagnetometerModelConfig ok;
  ok.soft_iron(0, 1) = 1e-6;
  EXPECT_NO_THROW(MagnetometerModel{ok});
}

}  // namespace
}  // namespace navaid::simulation
