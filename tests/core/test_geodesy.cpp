#include <gtest/gtest.h>

#include <limits>

#include "navaid/core/geodesy.hpp"

using namespace navaid;

TEST(Geodesy, EnuRoundTripAndAxes) {
  const LocalEnuFrame frame({44.069, -121.314, 1100.0});
  EXPECT_LT(frame.to_enu(44.069, -121.314, 1100.0).norm(), 1e-6);
  // Moving north raises y, moving east raises x, up raises z.
  EXPECT_GT(frame.to_enu(44.070, -121.314, 1100.0).y(), 100.0);
  EXPECT_GT(frame.to_enu(44.069, -121.313, 1100.0).x(), 70.0);
  EXPECT_NEAR(frame.to_enu(44.069, -121.314, 1110.0).z(), 10.0, 1e-6);
  const Vec3 p(123.4, -56.7, 8.9);
  const Vec3 geo = frame.to_geodetic(p);
  EXPECT_LT((frame.to_enu(geo.x(), geo.y(), geo.z()) - p).norm(), 1e-6);
  const LocalEnuFrame copy = frame;
  EXPECT_LT((copy.to_enu(geo.x(), geo.y(), geo.z()) - p).norm(), 1e-6);
}

TEST(Geodesy, KnownGeodesic) {
  // One degree of latitude at the equator on WGS84: 110574.389 m (meridian arc), due north.
  const auto line = geodesic_inverse(0.0, 0.0, 1.0, 0.0);
  EXPECT_NEAR(line.distance_m, 110574.389, 0.01);
  EXPECT_NEAR(line.azimuth_deg, 0.0, 1e-9);
  // One degree of longitude on the equator: a * pi / 180 = 111319.491 m, due east.
  const auto east = geodesic_inverse(0.0, 0.0, 0.0, 1.0);
  EXPECT_NEAR(east.distance_m, 111319.491, 0.01);
  EXPECT_NEAR(east.azimuth_deg, 90.0, 1e-9);
}

TEST(Geodesy, OriginFromFixesPrefersAMeasuredHeight) {
  GpsFix no_fix;
  no_fix.mode = GpsFixMode::kNoFix;
  GpsFix fix2d;
  fix2d.mode = GpsFixMode::k2D;
  fix2d.latitude_deg = 10;
  fix2d.longitude_deg = 20;
  fix2d.altitude_m = std::numeric_limits<double>::quiet_NaN();
  GpsFix fix3d = fix2d;
  fix3d.mode = GpsFixMode::k3D;
  fix3d.latitude_deg = 11;
  fix3d.altitude_m = 100;
  fix3d.geoid_separation_m = -20;
  EXPECT_FALSE(ellipsoidal_height_m(fix2d).has_value());
  EXPECT_DOUBLE_EQ(*ellipsoidal_height_m(fix3d), 80.0);
  const auto origin = origin_from_fixes({no_fix, fix2d, fix3d});
  ASSERT_TRUE(origin.has_value());
  EXPECT_DOUBLE_EQ(origin->latitude_deg, 11.0);
  EXPECT_DOUBLE_EQ(origin->height_m, 80.0);
  const auto flat = origin_from_fixes({no_fix, fix2d});
  ASSERT_TRUE(flat.has_value());
  EXPECT_DOUBLE_EQ(flat->latitude_deg, 10.0);
  EXPECT_DOUBLE_EQ(flat->height_m, 0.0);
  EXPECT_FALSE(origin_from_fixes({no_fix}).has_value());
}
