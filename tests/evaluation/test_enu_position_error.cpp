// ENU position error of GPS-aided runs and its rigid-registration reference: known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "navaid/core/geodesy.hpp"
#include "navaid/evaluation/enu_position_error.hpp"

namespace navaid::evaluation {
namespace {

constexpr Timestamp kSecond = 1'000'000'000;
const GeodeticOrigin kOrigin{31.0291, 121.4365, 12.0};

// An L-shaped walk at 1 m/s, ground truth at 10 Hz (W = ENU), 60 s.
std::vector<io::StampedPose> walk() {
  std::vector<io::StampedPose> gt;
  for (int i = 0; i <= 600; ++i) {
    const double s = 0.1 * i;
    const Vec3 p = s < 30 ? Vec3(s, 0, 0.1 * s) : Vec3(30, s - 30, 3.0);
    gt.push_back({i * kSecond / 10, SE3(Quat::Identity(), p)});
  }
  return gt;
}

// 1 Hz fixes at the antenna plus an offset (tangent-plane inverse: sub-millimetre at this scale).
std::vector<GpsFix> fixes_of(const std::vector<io::StampedPose>& gt, const Vec3& lever, const Vec3& offset) {
  const LocalEnuFrame frame(kOrigin);
  std::vector<GpsFix> fixes;
  for (std::size_t i = 0; i < gt.size(); i += 10) {
    const Vec3 geo = frame.to_geodetic(gt[i].T_W_B * lever + offset);
    GpsFix f;
    f.t = gt[i].t;
    f.mode = GpsFixMode::k3D;
    f.latitude_deg = geo.x();
    f.longitude_deg = geo.y();
    f.altitude_m = geo.z();
    f.geoid_separation_m = 0.0;
    f.covariance_enu = Vec3(9.0, 9.0, 25.0).asDiagonal();
    fixes.push_back(f);
  }
  return fixes;
}

TEST(EnuPositionError, SplitsHorizontalAndVertical) {
  const auto gt = walk();
  std::vector<io::StampedPose> est = gt;
  for (auto& p : est) p.T_W_B.t += Vec3(3.0, -4.0, 12.0);
  const auto e = enu_position_error(est, gt);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->poses, gt.size());
  EXPECT_NEAR(e->horizontal_rmse_m, 5.0, 1e-12);
  EXPECT_NEAR(e->vertical_rmse_m, 12.0, 1e-12);
  EXPECT_NEAR(e->rmse_m, 13.0, 1e-12);
  EXPECT_NEAR(e->max_m, 13.0, 1e-12);
  EXPECT_FALSE(enu_position_error({}, gt));
}

// A common offset of every fix (the multipath's mean over the walk) is what a rigid registration
// cannot tell from the truth: the reference error is that offset, wherever it is evaluated.
TEST(EnuPositionError, RigidRegistrationReferenceIsTheCommonOffset) {
  const auto gt = walk();
  const Vec3 lever(0.0, 0.1, 0.25);
  std::vector<Timestamp> times;
  for (std::size_t i = 0; i < gt.size(); i += 3) times.push_back(gt[i].t);
  const auto exact = rigid_registration_reference(fixes_of(gt, lever, Vec3::Zero()), gt, lever, kOrigin, times);
  ASSERT_TRUE(exact);
  EXPECT_LT(exact->rmse_m, 0.01);
  const auto shifted =
      rigid_registration_reference(fixes_of(gt, lever, Vec3(1.5, -2.0, 0.7)), gt, lever, kOrigin, times);
  ASSERT_TRUE(shifted);
  EXPECT_EQ(shifted->poses, times.size());
  EXPECT_NEAR(shifted->horizontal_rmse_m, 2.5, 0.01);
  EXPECT_NEAR(shifted->vertical_rmse_m, 0.7, 0.01);
  // Causal: the same offset once enough of the walk is in, nothing before the registration.
  const auto causal =
      causal_registration_reference(fixes_of(gt, lever, Vec3(1.5, -2.0, 0.7)), gt, lever, kOrigin, times);
  ASSERT_TRUE(causal);
  EXPECT_LT(causal->poses, times.size());
  EXPECT_GT(causal->poses, times.size() / 2);
  EXPECT_NEAR(causal->horizontal_rmse_m, 2.5, 0.01);
  EXPECT_NEAR(causal->vertical_rmse_m, 0.7, 0.01);
  // Too little motion to register (the first 3 s): no reference.
  const std::vector<io::StampedPose> start(gt.begin(), gt.begin() + 30);
  EXPECT_FALSE(rigid_registration_reference(fixes_of(start, lever, Vec3::Zero()), start, lever, kOrigin, times));
  EXPECT_FALSE(causal_registration_reference(fixes_of(start, lever, Vec3::Zero()), start, lever, kOrigin, times));
}

}  // namespace
}  // namespace navaid::evaluation
