// W-ROMA's hand rule (Sec. IV): backward when Z_h <= 0, forward when aligned, otherwise one of 8
// sectors of 45 deg of the image-plane angle theta = atan2(-Y_h, X_h) (0 right, +90 deg up), in
// which the paper's example [-157.5, -112.5] deg is "down left".
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/hand_sector.hpp"

namespace navaid::planning {
namespace {

HandDirection at_deg(double deg) { return sector_of_angle(deg_to_rad(deg)); }

/// A point at image-plane angle `deg`, lateral offset r, distance z (H: x right, y down).
Vec3 point_at(double deg, double r, double z) {
  const double t = deg_to_rad(deg);
  return Vec3(r * std::cos(t), -r * std::sin(t), z);
}

TEST(HandSector, PaperExampleDownLeftIsMinus157p5ToMinus112p5) {
  EXPECT_EQ(at_deg(-157.5), HandDirection::kDownLeft);
  EXPECT_EQ(at_deg(-135.0), HandDirection::kDownLeft);
  EXPECT_EQ(at_deg(-112.5 - 1e-6), HandDirection::kDownLeft);
  EXPECT_EQ(at_deg(-157.5 - 1e-6), HandDirection::kLeft);
  EXPECT_EQ(at_deg(-112.5), HandDirection::kDown);
  // The same through points: lower left of the image is X_h < 0, Y_h > 0 (y down).
  const HandSectorConfig c;
  EXPECT_EQ(hand_direction(Vec3(-0.2, 0.2, 1.0), c), HandDirection::kDownLeft);
  EXPECT_EQ(hand_direction(point_at(-150.0, 0.3, 1.0), c), HandDirection::kDownLeft);
  EXPECT_EQ(hand_direction(point_at(-120.0, 0.3, 1.0), c), HandDirection::kDownLeft);
  EXPECT_NEAR(rad_to_deg(image_plane_angle(Vec3(-0.2, 0.2, 1.0))), -135.0, 1e-12);
}

TEST(HandSector, EveryBoundaryBelongsToTheCounterClockwiseSector) {
  struct Boundary {
    double deg;
    HandDirection below, at;
  };
  const std::vector<Boundary> boundaries = {
      {-157.5, HandDirection::kLeft, HandDirection::kDownLeft},
      {-112.5, HandDirection::kDownLeft, HandDirection::kDown},
      {-67.5, HandDirection::kDown, HandDirection::kDownRight},
      {-22.5, HandDirection::kDownRight, HandDirection::kRight},
      {22.5, HandDirection::kRight, HandDirection::kUpRight},
      {67.5, HandDirection::kUpRight, HandDirection::kUp},
      {112.5, HandDirection::kUp, HandDirection::kUpLeft},
      {157.5, HandDirection::kUpLeft, HandDirection::kLeft},
  };
  for (const Boundary& b : boundaries) {
    EXPECT_EQ(at_deg(b.deg), b.at) << b.deg;
    EXPECT_EQ(at_deg(b.deg + 1e-4), b.at) << b.deg;
    EXPECT_EQ(at_deg(b.deg - 1e-4), b.below) << b.deg;
    // Wrapped by a full turn either way.
    EXPECT_EQ(at_deg(b.deg + 360.0), b.at) << b.deg;
    EXPECT_EQ(at_deg(b.deg - 360.0 - 1e-4), b.below) << b.deg;
  }
}

TEST(HandSector, SectorCentresAndTheLeftSeamAtPlusMinus180) {
  EXPECT_EQ(at_deg(0.0), HandDirection::kRight);
  EXPECT_EQ(at_deg(45.0), HandDirection::kUpRight);
  EXPECT_EQ(at_deg(90.0), HandDirection::kUp);
  EXPECT_EQ(at_deg(135.0), HandDirection::kUpLeft);
  EXPECT_EQ(at_deg(180.0), HandDirection::kLeft);
  EXPECT_EQ(at_deg(-180.0), HandDirection::kLeft);
  EXPECT_EQ(at_deg(-90.0), HandDirection::kDown);
  EXPECT_EQ(at_deg(-45.0), HandDirection::kDownRight);
}

TEST(HandSector, PointsInTheImageAxes) {
  const HandSectorConfig c;
  EXPECT_EQ(hand_direction(Vec3(0.3, 0.0, 1.0), c), HandDirection::kRight);
  EXPECT_EQ(hand_direction(Vec3(-0.3, 0.0, 1.0), c), HandDirection::kLeft);
  EXPECT_EQ(hand_direction(Vec3(0.0, -0.3, 1.0), c), HandDirection::kUp);    // y down: -y is up
  EXPECT_EQ(hand_direction(Vec3(0.0, 0.3, 1.0), c), HandDirection::kDown);
  EXPECT_EQ(hand_direction(Vec3(0.3, -0.3, 1.0), c), HandDirection::kUpRight);
  EXPECT_EQ(hand_direction(Vec3(-0.3, -0.3, 1.0), c), HandDirection::kUpLeft);
  EXPECT_EQ(hand_direction(Vec3(0.3, 0.3, 1.0), c), HandDirection::kDownRight);
}

TEST(HandSector, BackwardWhenZIsNotPositive) {
  const HandSectorConfig c;
  EXPECT_EQ(hand_direction(Vec3(0.0, 0.0, 0.0), c), HandDirection::kBackward);
  EXPECT_EQ(hand_direction(Vec3(0.5, -0.2, -0.1), c), HandDirection::kBackward);
  EXPECT_EQ(hand_direction(Vec3(0.5, 0.0, 1e-9), c), HandDirection::kRight);
  EXPECT_EQ(hand_direction_of_bearing(Vec3(0.1, 0.0, -1.0), c), HandDirection::kBackward);
  EXPECT_EQ(hand_direction(Vec3(NAN, 0.0, 1.0), c), HandDirection::kHold);
}

TEST(HandSector, ForwardInsideTheAlignedRadiusNearAndTheConeFar) {
  HandSectorConfig c;
  c.aligned_radius_m = 0.05;
  c.aligned_angle_rad = deg_to_rad(5.0);
  // Near (0.3 m): the 5 cm radius rules (0.3 tan 5 deg = 2.6 cm).
  EXPECT_EQ(hand_direction(point_at(30.0, 0.049, 0.3), c), HandDirection::kForward);
  EXPECT_EQ(hand_direction(point_at(30.0, 0.051, 0.3), c), HandDirection::kUpRight);
  // Far (3 m): the 5 deg cone rules (3 tan 5 deg = 26.2 cm).
  EXPECT_EQ(hand_direction(point_at(-90.0, 0.26, 3.0), c), HandDirection::kForward);
  EXPECT_EQ(hand_direction(point_at(-90.0, 0.27, 3.0), c), HandDirection::kDown);
  // Bearings: the cone only.
  EXPECT_EQ(hand_direction_of_bearing(point_at(0.0, std::tan(deg_to_rad(4.9)), 1.0), c), HandDirection::kForward);
  EXPECT_EQ(hand_direction_of_bearing(point_at(0.0, std::tan(deg_to_rad(5.1)), 1.0), c), HandDirection::kRight);
  EXPECT_EQ(hand_direction_of_bearing(point_at(-135.0, 1.0, 1.0), c), HandDirection::kDownLeft);
}

TEST(HandSector, ConfigKeysAreReadAndRangeChecked) {
  Config cfg = Config::parse("planning:\n  hand:\n    aligned_radius_m: 0.08\n    aligned_angle_deg: 10\n    reach_distance_m: 0.2\n");
  const HandSectorConfig c = read_hand_sector_config(cfg);
  EXPECT_DOUBLE_EQ(c.aligned_radius_m, 0.08);
  EXPECT_NEAR(c.aligned_angle_rad, deg_to_rad(10.0), 1e-15);
  EXPECT_DOUBLE_EQ(c.reach_distance_m, 0.2);
  EXPECT_THROW(read_hand_sector_config(Config::parse("planning:\n  hand:\n    aligned_angle_deg: 60\n")), ConfigError);
  EXPECT_THROW(read_hand_sector_config(Config::parse("planning:\n  hand:\n    aligned_radius_m: 0\n")), ConfigError);
  const HandSectorConfig d = read_hand_sector_config(Config());
  EXPECT_DOUBLE_EQ(d.aligned_radius_m, 0.05);
}

}  // namespace
}  // namespace navaid::planning
