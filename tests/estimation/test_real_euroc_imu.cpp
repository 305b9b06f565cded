// IMU preintegration on the real EuRoC V1_01 flight (ADIS16448, 145 s, rotor vibration): started
// from the ground-truth state (pose, velocity, biases) at a camera time, the preintegrated motion
// over short windows must land on the ground truth at the window's end. The simulator's IMU is
// kinder than this one; this is where the preintegration meets the world.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "navaid/estimation/imu_preintegration.hpp"
#include "navaid/io/euroc.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

struct WindowError {
  double position_m = 0, velocity_mps = 0, rotation_rad = 0;
};

TEST(RealEurocImu, PreintegrationOverHalfSecondWindowsLandsOnTheGroundTruth) {
  if (!navaid::testing::have_shared_data()) return;
  const io::Recording rec = io::read_euroc(navaid::testing::shared_data_dir() / "euroc-V1_01-micro");
  ASSERT_GT(rec.imu.size(), 29000u);
  ASSERT_GT(rec.groundtruth.size(), 2800u);
  ASSERT_TRUE(rec.calibration.imu.has_value());
  const ImuNoise noise = ImuNoise::from(*rec.calibration.imu);

  // Every 2.5 s of the flight (it takes off ~5 s in), a 0.5 s window between two ground-truth rows.
  std::vector<WindowError> errors;
  double worst_position = 0, worst_rotation = 0;
  for (std::size_t k = 200; k + 10 < rec.groundtruth.size(); k += 50) {
    const GroundTruthState& a = rec.groundtruth[k];
    const GroundTruthState& b = rec.groundtruth[k + 10];
    ASSERT_TRUE(a.v_W && a.b_g && a.b_a && b.v_W);
    if (b.t > rec.imu.back().t) break;
    const ImuPreintegration pre = ImuPreintegration::between(rec.imu, a.t, b.t, noise, *a.b_g, *a.b_a);
    SE3 T;
    Vec3 v;
    pre.predict(a.T_W_B, *a.v_W, *a.b_g, *a.b_a, &T, &v);
    WindowError e;
    e.position_m = (T.t - b.T_W_B.t).norm();
    e.velocity_mps = (v - *b.v_W).norm();
    e.rotation_rad = T.q.angularDistance(b.T_W_B.q);
    worst_position = std::max(worst_position, e.position_m);
    worst_rotation = std::max(worst_rotation, e.rotation_rad);
    errors.push_back(e);
  }
  ASSERT_GT(errors.size(), 50u);
  std::vector<double> p, r, v;
  for (const auto& e : errors) p.push_back(e.position_m), r.push_back(e.rotation_rad), v.push_back(e.velocity_mps);
  const auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2), x.end());
    return x[x.size() / 2];
  };
  std::printf("V1_01, %zu windows of 0.5 s: median |dp| %.4f m, |dv| %.4f m/s, |dR| %.4f deg; worst |dp| %.4f m, "
              "|dR| %.4f deg\n",
              errors.size(), median(p), median(v), median(r) * 180 / M_PI, worst_position, worst_rotation * 180 / M_PI);
  // Measured: 5.8 mm, 0.023 m/s, 0.051 deg median; worst 12 mm, 0.12 deg.
  EXPECT_LT(median(p), 0.015);
  EXPECT_LT(median(v), 0.06);
  EXPECT_LT(median(r), 0.15 * M_PI / 180);
  EXPECT_LT(worst_position, 0.04);
  EXPECT_LT(worst_rotation, 0.5 * M_PI / 180);
}

}  // namespace
}  // namespace navaid::estimation
