// The Mapper acts on the estimate: unlocalised and unsure frames are not mapped (counted), frames
// without depth are skipped (counted), and the cost map keeps more clearance when the estimator is
// less sure.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "navaid/mapping/mapper.hpp"

namespace navaid::mapping {
namespace {

CameraCalibration forward_camera() {
  CameraCalibration c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 100;
  c.cx = 80;
  c.cy = 60;
  // Optical axis along the body x axis (forward), image x to the body's right, y down.
  Mat3 R_B_C;
  R_B_C.col(0) = -Vec3::UnitY();
  R_B_C.col(1) = -Vec3::UnitZ();
  R_B_C.col(2) = Vec3::UnitX();
  c.T_B_C = SE3(R_B_C, Vec3::Zero());
  return c;
}

/// A wall 2 m ahead filling the image, labelled wall.
RgbdFrame wall_frame() {
  RgbdFrame f;
  f.depth = ImageF32(160, 120, 1, 2.0f);
  f.labels = ImageU8(160, 120, 1, static_cast<std::uint8_t>(SemanticClass::kWall));
  f.label_confidence = ImageF32(160, 120, 1, 0.9f);
  return f;
}

StateEstimate estimate(double sigma_xy, EstimatorMode mode = EstimatorMode::kRgbdVio) {
  StateEstimate e;
  e.mode = mode;
  e.T_W_B = SE3(Quat::Identity(), Vec3(0, 0, 1.0));
  e.covariance = Mat15::Identity() * 1e-6;
  e.covariance(3, 3) = e.covariance(4, 4) = sigma_xy * sigma_xy;
  return e;
}

MapperConfig config() {
  MapperConfig c;
  c.cloud.pixel_stride = 2;
  // The scene is a wall alone (no floor for the undulation map to see a step from): make all of its
  // height collide, so that eq. (9) gives 1 on the wall's cells.
  c.collision.min_relative_height_m = -1.5;
  c.collision.max_relative_height_m = 1.5;
  return c;
}

MapperConfig absolute_config() {
  MapperConfig c = config();
  c.gate.scope = UncertaintyScope::kAbsolute;  // one frame per case: no history to take a gain over
  return c;
}

TEST(Mapper, SkipsWhatItMustNotMapAndCountsIt) {
  Mapper mapper(absolute_config(), forward_camera());
  EXPECT_EQ(mapper.process(wall_frame(), estimate(0.01, EstimatorMode::kInitializing)).outcome,
            FrameOutcome::kNotLocalised);
  EXPECT_EQ(mapper.process(wall_frame(), estimate(0.01, EstimatorMode::kLost)).outcome, FrameOutcome::kNotLocalised);
  EXPECT_EQ(mapper.process(wall_frame(), estimate(0.8)).outcome, FrameOutcome::kTooUncertain);
  RgbdFrame no_depth = wall_frame();
  no_depth.depth = ImageF32();
  EXPECT_EQ(mapper.process(no_depth, estimate(0.01)).outcome, FrameOutcome::kNoDepth);
  EXPECT_EQ(mapper.map().leaf_count(), 0u);  // nothing of the above reached the map
  EXPECT_EQ(mapper.local_maps(), nullptr);
  const auto r = mapper.process(wall_frame(), estimate(0.01));
  EXPECT_EQ(r.outcome, FrameOutcome::kMapped);
  EXPECT_GT(r.points, 0u);
  const auto& n = mapper.counters();
  EXPECT_EQ(n.frames, 5u);
  EXPECT_EQ(n.not_localised, 2u);
  EXPECT_EQ(n.too_uncertain, 1u);
  EXPECT_EQ(n.no_depth, 1u);
  EXPECT_EQ(n.mapped, 1u);
  ASSERT_NE(mapper.local_maps(), nullptr);
  EXPECT_TRUE(mapper.map().voxel_at(Vec3(2.05, 0.05, 1.05)).has_value());
}

/// Cells of the cost map that are obstacles.
std::size_t blocked_cells(const CostMap& cost) {
  std::size_t n = 0;
  for (int y = 0; y < cost.geometry().height(); ++y)
    for (int x = 0; x < cost.geometry().width(); ++x) n += cost.is_obstacle(x, y);
  return n;
}

const LocalMaps& maps_of(const Mapper& m) {
  if (m.local_maps() == nullptr) throw std::runtime_error("the mapper built no local maps");
  return *m.local_maps();
}

TEST(Mapper, ALessSureEstimateBlocksMoreOfTheCostMap) {
  Mapper sure(absolute_config(), forward_camera()), unsure(absolute_config(), forward_camera());
  sure.process(wall_frame(), estimate(0.01));
  unsure.process(wall_frame(), estimate(0.2));  // under the 0.5 m gate: mapped, but inflated
  const std::size_t a = blocked_cells(maps_of(sure).cost), b = blocked_cells(maps_of(unsure).cost);
  EXPECT_GT(a, 0u);
  EXPECT_GT(b, a + 100);  // k = 2: 0.4 m of inflation on both sides of the wall's cells
  // The ESDF follows: the camera position is nearer the (inflated) obstacles.
  const auto d_sure = maps_of(sure).esdf.distance(Eigen::Vector2d(0.5, 0.0));
  const auto d_unsure = maps_of(unsure).esdf.distance(Eigen::Vector2d(0.5, 0.0));
  ASSERT_TRUE(d_sure && d_unsure);
  EXPECT_LT(*d_unsure, *d_sure - 0.3);
}

/// An estimate at t [s] whose horizontal sigma is sigma_xy.
StateEstimate at(double t_s, double sigma_xy) {
  StateEstimate e = estimate(sigma_xy);
  e.t = static_cast<Timestamp>(t_s * 1e9);
  return e;
}

TEST(Mapper, WindowScopeGatesOnWhatTheEstimateLostRecentlyAbsoluteOnItsWholeSigma) {
  // Drift as a visual-inertial estimator's: sigma_xy grows to 1 m over 100 s (random walk:
  // sigma^2 linear in time). Over a 10 s window it gains sqrt(1 - 0.9) = 0.32 m: still mapped.
  MapperConfig window = config(), absolute = config();
  absolute.gate.scope = UncertaintyScope::kAbsolute;
  absolute.layers = window.layers = false;
  Mapper w(window, forward_camera()), a(absolute, forward_camera());
  for (int k = 0; k <= 100; ++k) {
    const double t = k, sigma = std::sqrt(t / 100.0) + 1e-3;
    const auto rw = w.process(wall_frame(), at(t, sigma));
    const auto ra = a.process(wall_frame(), at(t, sigma));
    EXPECT_EQ(ra.outcome, sigma > 0.5 ? FrameOutcome::kTooUncertain : FrameOutcome::kMapped) << t;
    EXPECT_EQ(rw.outcome, FrameOutcome::kMapped) << t;
    EXPECT_LT(rw.gated.sigma_xy, 0.5);
  }
  EXPECT_EQ(w.counters().too_uncertain, 0u);
  EXPECT_EQ(a.counters().too_uncertain, 76u);  // sigma > 0.5 m from t = 25 s on
  // A jump (the estimator lost its visual track for a moment): 0.3 m -> 1.2 m within a second.
  const auto jump = w.process(wall_frame(), at(101, 1.2));
  EXPECT_EQ(jump.outcome, FrameOutcome::kTooUncertain);
  EXPECT_NEAR(jump.gated.sigma_xy, std::sqrt(1.2 * 1.2 - 0.9), 0.05);
}

}  // namespace
}  // namespace navaid::mapping
