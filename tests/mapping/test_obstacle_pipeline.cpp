// The augmented-cane obstacle pipeline (thesis Ch. 2): synthetic scenes with known geometry
// rendered by the simulator's ray caster, kerbs and steps, real Kinect clouds (PCL's test data)
// and rendered cane-mount frames of the corridor and obstacle-course scenarios.
#include "navaid/mapping/obstacle_pipeline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/mapping/pcd_cloud.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/sensor_rig.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/walker_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

using simulation::Box;
using simulation::PlanePatch;
using simulation::RayCaster;
using simulation::Surface;
using simulation::VerticalCylinder;
using simulation::World;

constexpr double kDeg = ObstaclePipelineConfig::kDeg;
constexpr double kPi = 3.14159265358979323846;

// An Asus Xtion-like depth camera (58° horizontal view, as in the thesis) at reduced resolution.
CameraCalibration xtion(int width = 320, int height = 240) {
  CameraCalibration c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.5 * width / std::tan(29.0 * kDeg);
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  return c;
}

const Surface kFloorSurface{SemanticClass::kFloor, 1, 0.1, 0.7};
const Surface kObstacleSurface{SemanticClass::kPole, 2, 0.05, 0.6};

// Camera points of `world` seen from T_W_C through the noise-free renderer.
std::vector<Eigen::Vector3f> render_points(const World& world, const SE3& T_W_C, const CameraCalibration& calib = xtion()) {
  const RayCaster caster(world);
  const auto camera = make_camera_model(calib);
  simulation::RenderOptions options;
  options.max_depth = 8.0;
  options.render_labels = options.render_intensity = false;
  RgbdFrame frame;
  frame.depth = simulation::RgbdRenderer(caster, *camera).render(T_W_C, options).depth;
  return camera_points_from_depth(frame, calib);
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Vec3 on_bearing(double bearing_deg, double range_m, double z = 0.0) {
  return Vec3(range_m * std::cos(bearing_deg * kDeg), range_m * std::sin(bearing_deg * kDeg), z);
}

// A camera 0.9 m above the floor, pitched down 20° and rolled 3°: W = the true U frame.
const SE3 kTrueT_U_C = level_camera_T_U_C(0.9, 20.0 * kDeg) * SE3(Quat(Eigen::AngleAxisd(3.0 * kDeg, Vec3::UnitZ())), Vec3::Zero());
// What an IMU-less prior would say: right height and pitch within 5°, no roll.
const SE3 kPrior = level_camera_T_U_C(0.85, 15.0 * kDeg);

struct Pole {
  double bearing_deg, range_m;
};
const std::vector<Pole> kPoles = {{0.0, 2.0}, {12.0, 3.0}, {-17.0, 1.6}, {22.0, 2.4}};
constexpr double kPoleRadius = 0.03;

World floor_with_poles() {
  World w;
  w.add(PlanePatch{SE3(), 20.0, 20.0}, kFloorSurface);
  for (const Pole& p : kPoles)
    w.add(VerticalCylinder{on_bearing(p.bearing_deg, p.range_m), kPoleRadius, 1.5}, kObstacleSurface);
  return w;
}

TEST(ObstaclePipeline, TiltedCameraFindsFloorPlaneAndPolesInTheirBins) {
  ObstaclePipeline pipeline;
  const ObstacleScan scan = pipeline.process(render_points(floor_with_poles(), kTrueT_U_C), kPrior, 42);
  EXPECT_EQ(scan.t, 42);
  const ObstacleScanCounters& n = scan.counters;
  EXPECT_TRUE(n.ransac_succeeded);
  EXPECT_FALSE(n.running_average_used);
  EXPECT_EQ(n.ground_source, GroundSource::kRansac);
  EXPECT_EQ(n.points_in, 320u * 240u);
  EXPECT_LT(n.after_voxel_grid, n.points_in - n.non_finite);
  EXPECT_GT(n.ground_inliers, n.after_voxel_grid / 2);

  const GroundPlane truth = ground_plane_of(kTrueT_U_C);
  EXPECT_LT(angle_between(scan.ground.normal_C, truth.normal_C), 1.0 * kDeg);
  EXPECT_NEAR(scan.ground.offset_m, 0.9, 0.01);
  // The refined alignment levels U: the true up axis maps onto z_U.
  EXPECT_LT(angle_between(scan.T_U_C.q * truth.normal_C, Vec3::UnitZ()), 1.0 * kDeg);

  ASSERT_EQ(scan.size(), 61u);  // thesis App. D.2: -30°..30° in 1° bins
  EXPECT_NEAR(scan.bearing(0), -30.0 * kDeg, 1e-12);
  for (const Pole& p : kPoles) {
    const auto bin = scan.bin_of(p.bearing_deg * kDeg);
    ASSERT_TRUE(bin);
    EXPECT_NEAR(scan.ranges[*bin], p.range_m - kPoleRadius, 0.02) << "pole at " << p.bearing_deg << "°";
    EXPECT_GT(scan.nearest_U[*bin].z(), 0.1f);
  }
  // Nothing else: bins more than the pole's angular half-width + 1 bin away from a pole are clear.
  for (std::size_t i = 0; i < scan.size(); ++i) {
    bool near_pole = false;
    for (const Pole& p : kPoles) near_pole |= std::abs(scan.bearing(i) / kDeg - p.bearing_deg) <= 2.5;
    if (!near_pole) {
      EXPECT_FALSE(scan.has_obstacle(i)) << "bin " << scan.bearing(i) / kDeg << "° at " << scan.ranges[i] << " m";
      EXPECT_TRUE(std::isnan(scan.nearest_U[i].x()));
    }
    EXPECT_FALSE(scan.has_drop_off(i));
  }
  EXPECT_EQ(n.drop_off_points, 0u);
}

TEST(ObstaclePipeline, AboveHeadPointsAreRemovedAndWhatIsBehindThemReported) {
  // Camera nearly level so that it sees above 2 m: a wall 5 m ahead (3 m high) and a board
  // hanging at 2.2-2.5 m, 3 m ahead at 10°.
  World w;
  w.add(PlanePatch{SE3(), 20.0, 20.0}, kFloorSurface);
  w.add(Box{SE3(Quat::Identity(), Vec3(5.1, 0.0, 1.5)), Vec3(0.1, 6.0, 1.5)}, kObstacleSurface);
  w.add(Box{SE3(Quat::Identity(), on_bearing(10.0, 3.0, 2.35)), Vec3(0.1, 0.4, 0.15)}, kObstacleSurface);
  const SE3 T_U_C = level_camera_T_U_C(0.9, 5.0 * kDeg);
  ObstaclePipeline pipeline;
  const ObstacleScan scan = pipeline.process(render_points(w, T_U_C), level_camera_T_U_C(0.9, 0.0));
  EXPECT_EQ(scan.counters.ground_source, GroundSource::kRansac);
  EXPECT_GT(scan.counters.above_head_removed, 1000u);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double b = scan.bearing(i);
    if (std::abs(b) > 26.0 * kDeg) continue;  // the corners of the view miss the wall's base
    ASSERT_TRUE(scan.has_obstacle(i)) << b / kDeg;
    EXPECT_NEAR(scan.ranges[i], 5.0 / std::cos(b), 0.03) << "bin " << b / kDeg << "° sees the wall, not the board";
    EXPECT_LE(scan.nearest_U[i].z(), 2.0f);
  }
}

// Frames with a floor feed the running average; then frames without one.
TEST(ObstaclePipeline, NoFloorFirstFrameUsesThePrior) {
  World wall;
  wall.add(Box{SE3(Quat::Identity(), Vec3(1.1, 0.0, 1.5)), Vec3(0.1, 5.0, 1.5)}, kObstacleSurface);
  const SE3 level = level_camera_T_U_C(0.9, 0.0);
  ObstaclePipeline pipeline;
  const ObstacleScan scan = pipeline.process(render_points(wall, level), level_camera_T_U_C(1.1, 0.0));
  EXPECT_FALSE(scan.counters.ransac_succeeded);
  EXPECT_FALSE(scan.counters.running_average_used);
  EXPECT_EQ(scan.counters.ground_source, GroundSource::kPrior);
  EXPECT_NEAR(scan.ground.offset_m, 1.1, 1e-12);  // the prior's plane, as given
  EXPECT_EQ(pipeline.running_average_count(), 0u);
}

TEST(ObstaclePipeline, NoFloorFrameFallsBackToTheRunningAverage) {
  ObstaclePipeline pipeline;
  const auto floor_points = render_points(floor_with_poles(), kTrueT_U_C);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(pipeline.process(floor_points, kPrior).counters.ground_source, GroundSource::kRansac);
  ASSERT_EQ(pipeline.running_average_count(), 3u);
  const GroundPlane average = pipeline.running_average_plane();
  EXPECT_NEAR(average.offset_m, 0.9, 0.01);

  // A wall 1 m ahead fills the view: RANSAC finds no plane within 15° of the up axis.
  World wall;
  wall.add(Box{SE3(Quat::Identity(), Vec3(1.1, 0.0, 1.5)), Vec3(0.1, 5.0, 1.5)}, kObstacleSurface);
  const ObstacleScan scan = pipeline.process(render_points(wall, level_camera_T_U_C(0.9, 0.0)), kPrior);
  const ObstacleScanCounters& n = scan.counters;
  EXPECT_FALSE(n.ransac_succeeded);
  EXPECT_TRUE(n.running_average_used);
  EXPECT_EQ(n.ground_source, GroundSource::kRunningAverageNoPlane);
  EXPECT_EQ(scan.ground.offset_m, average.offset_m);
  EXPECT_EQ(scan.ground.normal_C, average.normal_C);
  EXPECT_EQ(pipeline.running_average_count(), 3u);  // a fallback frame does not feed the average
  EXPECT_GT(n.obstacle_points, 1000u);
  // The wall is reported where the camera looks (the average's alignment is the tilted
  // camera's, so the level wall camera is misaligned by ~20°: ranges are only checked coarsely).
  EXPECT_LT(scan.min_range(), 1.2f);
}

TEST(ObstaclePipeline, TableTopIsAFalseGroundAndTheAveragePlaneIsUsed) {
  ObstaclePipeline pipeline;
  const auto floor_points = render_points(floor_with_poles(), kTrueT_U_C);
  for (int k = 0; k < 2; ++k) pipeline.process(floor_points, kPrior);
  // A table top 0.72 m high covers the whole view (thesis: "a table or countertop").
  World table;
  table.add(PlanePatch{SE3(), 20.0, 20.0}, kFloorSurface);
  table.add(Box{SE3(Quat::Identity(), Vec3(2.3, 0.0, 0.36)), Vec3(2.0, 3.0, 0.36)}, Surface{SemanticClass::kTable, 3, 0.05, 0.6});
  const ObstacleScan scan = pipeline.process(render_points(table, kTrueT_U_C), kPrior);
  const ObstacleScanCounters& n = scan.counters;
  EXPECT_TRUE(n.ransac_succeeded);
  EXPECT_TRUE(n.running_average_used);
  EXPECT_EQ(n.ground_source, GroundSource::kRunningAverageRejected);
  EXPECT_NEAR(scan.ground.offset_m, pipeline.running_average_plane().offset_m, 1e-12);
  EXPECT_NEAR(scan.ground.offset_m, 0.9, 0.01);
  EXPECT_EQ(pipeline.running_average_count(), 2u);
  // The table is an obstacle: its front face at x = 0.3 m (the lowest ray meets it at 0.63 m).
  const auto ahead = scan.bin_of(0.0);
  ASSERT_TRUE(ahead && scan.has_obstacle(*ahead));
  EXPECT_NEAR(scan.ranges[*ahead], 0.3, 0.02);
  EXPECT_GT(scan.nearest_U[*ahead].z(), 0.5f);
  EXPECT_LT(scan.nearest_U[*ahead].z(), 0.73f);
}

// Kerbs and steps: the user stands at x < 2 m, a second level starts at x = 2 m.
World two_levels(double step_m) {
  World w;
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0.0, 0.0, 0.0)), 2.0, 10.0}, Surface{SemanticClass::kSidewalk, 1, 0.1, 0.7});
  if (step_m < 0) {
    w.add(PlanePatch{SE3(Quat::Identity(), Vec3(8.0, 0.0, step_m)), 6.0, 10.0}, Surface{SemanticClass::kRoad, 4, 0.1, 0.5});
  } else {
    w.add(Box{SE3(Quat::Identity(), Vec3(8.0, 0.0, 0.5 * step_m)), Vec3(6.0, 10.0, 0.5 * step_m)},
          Surface{SemanticClass::kSidewalk, 5, 0.1, 0.6});
  }
  return w;
}
// The cane camera: 0.8 m, looking 25° down (simulator's cane mount).
const SE3 kCane = level_camera_T_U_C(0.8, 25.0 * kDeg);

TEST(ObstaclePipeline, KerbSteppedDownIsADropOffNotAWall) {
  ObstaclePipeline pipeline;
  const ObstacleScan scan = pipeline.process(render_points(two_levels(-0.15), kCane), kCane);
  EXPECT_NEAR(scan.ground.offset_m, 0.8, 0.01) << "the ground is the level the user stands on";
  EXPECT_EQ(scan.counters.obstacle_points, 0u);
  EXPECT_GT(scan.counters.drop_off_points, 1000u);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_FALSE(scan.has_obstacle(i)) << scan.bearing(i) / kDeg << "° at " << scan.ranges[i];
    // Over the kerb edge (x = 2, z = 0) the camera first sees the road at x = 2 * 0.95 / 0.8.
    ASSERT_TRUE(scan.has_drop_off(i)) << scan.bearing(i) / kDeg;
    EXPECT_NEAR(scan.drop_off_ranges[i], 2.375 / std::cos(scan.bearing(i)), 0.05);
    EXPECT_NEAR(scan.drop_off_nearest_U[i].z(), -0.15, 0.03);
  }
}

TEST(ObstaclePipeline, StepUpAboveTheInlierBandIsAnObstacle) {
  ObstaclePipeline pipeline;
  const ObstacleScan scan = pipeline.process(render_points(two_levels(0.15), kCane), kCane);
  EXPECT_NEAR(scan.ground.offset_m, 0.8, 0.01);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ASSERT_TRUE(scan.has_obstacle(i)) << scan.bearing(i) / kDeg;
    EXPECT_NEAR(scan.ranges[i], 2.0 / std::cos(scan.bearing(i)), 0.03);
    EXPECT_FALSE(scan.has_drop_off(i));
  }
}

TEST(ObstaclePipeline, StepWithinTheInlierBandIsGround) {
  // 5 cm is inside RANSAC's 0.1 m band: stepped over like the floor (documented threshold).
  ObstaclePipeline pipeline;
  for (double step : {0.05, -0.05}) {
    const ObstacleScan scan = pipeline.process(render_points(two_levels(step), kCane), kCane);
    EXPECT_EQ(scan.min_range(), std::numeric_limits<float>::infinity()) << step;
    for (std::size_t b = 0; b < scan.size(); ++b) EXPECT_FALSE(scan.has_drop_off(b)) << step << " at " << scan.bearing(b) / kDeg;
  }
}

TEST(ObstaclePipeline, EmptyAndNonFiniteInput) {
  ObstaclePipeline pipeline;
  const ObstacleScan empty = pipeline.process({}, kPrior);
  EXPECT_EQ(empty.size(), 61u);
  EXPECT_EQ(empty.min_range(), std::numeric_limits<float>::infinity());
  EXPECT_EQ(empty.counters.points_in, 0u);
  EXPECT_EQ(empty.counters.ground_source, GroundSource::kPrior);

  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<Eigen::Vector3f> junk = {{nan, 0, 1}, {0, inf, 1}, {0, 0, -inf}, {nan, nan, nan}};
  const ObstacleScan none = pipeline.process(junk, kPrior);
  EXPECT_EQ(none.counters.points_in, 4u);
  EXPECT_EQ(none.counters.non_finite, 4u);
  EXPECT_EQ(none.counters.after_voxel_grid, 0u);
  EXPECT_EQ(none.min_range(), inf);

  // Non-finite points among a real frame are skipped without changing the result.
  std::vector<Eigen::Vector3f> points = render_points(floor_with_poles(), kTrueT_U_C);
  const std::size_t invalid = static_cast<std::size_t>(std::count_if(points.begin(), points.end(), [](const Eigen::Vector3f& p) { return !p.allFinite(); }));
  points.insert(points.begin(), junk.begin(), junk.end());
  ObstaclePipeline fresh;
  const ObstacleScan scan = fresh.process(points, kPrior);
  EXPECT_EQ(scan.counters.non_finite, invalid + 4);
  EXPECT_EQ(scan.counters.ground_source, GroundSource::kRansac);
  EXPECT_NEAR(scan.ranges[*scan.bin_of(0.0)], 2.0 - kPoleRadius, 0.02);
}

TEST(ObstaclePipeline, DepthImageBackProjection) {
  CameraCalibration calib = xtion(8, 6);
  RgbdFrame frame;
  frame.depth = ImageF32(8, 6, 1, 2.0f);
  frame.depth.at(3, 2) = 0.0f;
  const auto all = camera_points_from_depth(frame, calib);
  ASSERT_EQ(all.size(), 48u);
  EXPECT_FALSE(all[2 * 8 + 3].allFinite());
  EXPECT_NEAR(all[0].x(), -calib.cx / calib.fx * 2.0, 1e-6);
  EXPECT_NEAR(all[0].z(), 2.0, 1e-6);
  EXPECT_EQ(camera_points_from_depth(frame, calib, 3).size(), 3u * 2u);
  EXPECT_THROW(camera_points_from_depth(frame, calib, 0), Error);
  EXPECT_THROW(camera_points_from_depth(RgbdFrame{}, calib), Error);
  EXPECT_THROW(camera_points_from_depth(frame, xtion(16, 12)), Error);
}

TEST(ObstaclePipeline, ConfigKeysAreReadAndRangeChecked) {
  const Config c = Config::parse("mapping: {obstacles: {voxel_leaf_size: 0.02, ransac: {eps_angle: 20}, scan: {min_bearing: -43, max_bearing: 43}}}");
  const ObstaclePipelineConfig o = read_obstacle_pipeline_config(c);
  EXPECT_DOUBLE_EQ(o.voxel_leaf_size_m, 0.02);
  EXPECT_NEAR(o.ransac_eps_angle_rad, 20.0 * kDeg, 1e-12);
  EXPECT_EQ(o.scan_bins(), 87u);
  EXPECT_DOUBLE_EQ(o.above_head_height_m, 2.0);
  c.reject_unknown_keys(obstacle_pipeline_config_schema());
  const std::string msg = testing::error_message<ConfigError>(
      [] { read_obstacle_pipeline_config(Config::parse("{}", "<t>", {"mapping.obstacles.ransac.distance_threshold=-1"})); });
  EXPECT_NE(msg.find("mapping.obstacles.ransac.distance_threshold"), std::string::npos) << msg;
  EXPECT_THROW(read_obstacle_pipeline_config(Config::parse("{}", "<t>", {"mapping.obstacles.scan.min_bearing=40"})), ConfigError);
  ObstaclePipelineConfig bad;
  bad.above_head_height_m = 0.0;
  EXPECT_THROW(ObstaclePipeline{bad}, ConfigError);
}

TEST(ObstaclePipeline, LevelPriorAlignmentIsTheThesisAxisAngle) {
  // Thesis eq. 2.6-2.8: rotation acos(-B) about (C, 0, -A)/|.| levels the sensor; then the fixed
  // optical-to-user axes permutation (App. C's static transform -pi/2, -pi/2). Exact for a
  // pitched camera (A = 0).
  GroundPlane g;
  g.normal_C = Eigen::Vector3d(0.0, -0.95, -0.3).normalized();
  g.offset_m = 1.2;
  const SE3 T = user_frame_from_ground(g, level_camera_T_U_C(1.0));
  auto thesis = [](const Eigen::Vector3d& n) {
    const Eigen::AngleAxisd level(std::acos(-n.y()), Eigen::Vector3d(n.z(), 0, -n.x()).normalized());
    return Mat3(level_camera_T_U_C(1.0).rotation() * level.toRotationMatrix());
  };
  EXPECT_TRUE(T.rotation().isApprox(thesis(g.normal_C), 1e-9));
  EXPECT_NEAR((T * Vec3(g.normal_C * -g.offset_m)).z(), 0.0, 1e-9);  // the foot point is on z_U = 0
  EXPECT_NEAR(T.t.z(), 1.2, 1e-12);

  // Rolled as well: both level the normal; ours keeps the optical axis at bearing 0, the thesis's
  // rotation turns it by ~ roll x sin(pitch).
  g.normal_C = Eigen::Vector3d(0.1, -0.94, -0.3).normalized();
  const SE3 R = user_frame_from_ground(g, level_camera_T_U_C(1.0));
  EXPECT_LT(angle_between(R.q * g.normal_C, Vec3::UnitZ()), 1e-9);
  EXPECT_LT(angle_between(thesis(g.normal_C) * g.normal_C, Vec3::UnitZ()), 1e-9);
  const Vec3 axis = R.q * Vec3::UnitZ(), thesis_axis = thesis(g.normal_C) * Vec3::UnitZ();
  EXPECT_NEAR(std::atan2(axis.y(), axis.x()), 0.0, 1e-9);
  EXPECT_GT(std::abs(std::atan2(thesis_axis.y(), thesis_axis.x())), 0.5 * kDeg);
}

// ---- Real Kinect clouds (PCL's test data) -------------------------------------------------------

std::filesystem::path pcl_cloud(const std::string& name) { return testing::shared_data_dir() / "pcl-clouds" / name; }

// Runs of adjacent occupied bins whose ranges differ by less than `jump` [m].
std::vector<std::pair<std::size_t, std::size_t>> range_clusters(const ObstacleScan& s, double max_range, double jump) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!(s.ranges[i] < max_range)) continue;
    if (!out.empty() && out.back().second + 1 == i && std::abs(s.ranges[i] - s.ranges[i - 1]) < jump)
      out.back().second = i;
    else
      out.emplace_back(i, i);
  }
  return out;
}

// Every voxel ends up in exactly one class.
void expect_counters_add_up(const ObstacleScan& scan, const std::string& name) {
  const ObstacleScanCounters& n = scan.counters;
  EXPECT_EQ(n.ground_inliers + n.above_head_removed + n.drop_off_points + n.obstacle_points, n.after_voxel_grid) << name;
  EXPECT_LE(n.after_voxel_grid, n.points_in - n.non_finite) << name;
  EXPECT_LE(n.outside_scan, n.drop_off_points + n.obstacle_points) << name;
}

TEST(ObstaclePipeline, FivePeopleKinectFloorAndPeople) {
  NAVAID_REQUIRE_SHARED_DATA();
  const PcdCloud cloud = read_pcd_cloud(pcl_cloud("five_people.pcd"));
  ObstaclePipeline pipeline;
  const ObstacleScan scan = pipeline.process(cloud.points, level_camera_T_U_C(1.0));
  ASSERT_EQ(scan.counters.ground_source, GroundSource::kRansac);
  // PCL's people-detection test: ax + by + cz + d = 0 with the normal pointing down (y down).
  const Eigen::Vector3d ref_n(-0.0103586, 0.997011, 0.0765573);
  const double ref_d = -1.26614;
  const double angle = angle_between(scan.ground.normal_C, -ref_n.normalized());
  const double offset_error = scan.ground.offset_m - (-ref_d / ref_n.norm());
  ::testing::Test::RecordProperty("plane_angle_error_deg", std::to_string(angle / kDeg));
  ::testing::Test::RecordProperty("plane_offset_error_cm", std::to_string(100 * offset_error));
  EXPECT_LT(angle, 2.0 * kDeg);
  EXPECT_LT(std::abs(offset_error), 0.03);

  std::printf("five_people: plane %.2f deg / %.2f cm off PCL's reference\n", angle / kDeg, 100 * offset_error);
  // The five people stand side by side 1.9-2.9 m away and fill the view: a person is a run of
  // bins whose range changes by < 0.1 m from bin to bin, at least 5° wide (0.17 m at 2 m), nearer
  // than 4 m (the room behind them is farther). Two bins at the left edge (2.9 m) are a partial
  // object at the border of the view, too narrow for a person.
  std::string printed;
  for (std::size_t i = 0; i < scan.size(); ++i) printed += " " + std::to_string(scan.ranges[i]).substr(0, 4);
  std::size_t people = 0;
  for (const auto& [first, last] : range_clusters(scan, 4.0, 0.1)) people += last - first + 1 >= 5;
  ::testing::Test::RecordProperty("people_found", static_cast<int>(people));
  EXPECT_EQ(people, 5u) << printed;
  expect_counters_add_up(scan, "five_people.pcd");
}

TEST(ObstaclePipeline, TableSceneAndOfficeCloudsFindAPlane) {
  NAVAID_REQUIRE_SHARED_DATA();
  for (const std::string name : {"table_scene_mug_stereo_textured.pcd", "office1.pcd", "five_people.pcd"}) {
    const PcdCloud cloud = read_pcd_cloud(pcl_cloud(name));
    ObstaclePipeline pipeline;
    const ObstacleScan scan = pipeline.process(cloud.points, level_camera_T_U_C(1.0));
    EXPECT_EQ(scan.counters.points_in, 640u * 480u) << name;
    EXPECT_GT(scan.counters.non_finite, 0u) << name;
    EXPECT_TRUE(scan.counters.ransac_succeeded) << name;
    EXPECT_EQ(scan.counters.ground_source, GroundSource::kRansac) << name;
    // RANSAC's hypotheses are within 15° of the camera's -y axis; the least-squares refits may
    // move the plane a little beyond (table_scene: 15.6°, the table top seen from above).
    EXPECT_LE(angle_between(scan.ground.normal_C, -Eigen::Vector3d::UnitY()), 17.0 * kDeg) << name;
    EXPECT_GT(scan.counters.obstacle_points, 0u) << name;
    expect_counters_add_up(scan, name);
  }
}

TEST(ObstaclePipeline, GrabberSequenceKeepsTheRunningAverageConsistent) {
  NAVAID_REQUIRE_SHARED_DATA();
  // Three consecutive OpenNI frames of one sequence through one pipeline: each frame either
  // agrees with the running average (and joins it) or is rejected and uses the average's plane.
  ObstaclePipeline pipeline;
  for (const std::string stamp : {"142255.814212", "142256.068683", "142256.332395"}) {
    const std::string name = "grabber_sequences/pcd/frame_20121214T" + stamp + ".pcd";
    const std::size_t before = pipeline.running_average_count();
    const GroundPlane average = pipeline.running_average_plane();
    const ObstacleScan scan = pipeline.process(read_pcd_cloud(pcl_cloud(name)).points, level_camera_T_U_C(1.0));
    EXPECT_TRUE(scan.counters.ransac_succeeded) << name;
    expect_counters_add_up(scan, name);
    if (scan.counters.ground_source == GroundSource::kRansac) {
      EXPECT_EQ(pipeline.running_average_count(), before + 1) << name;
      if (before > 0) {
        EXPECT_LE(std::abs(scan.ground.offset_m - average.offset_m), 0.2) << name;
      }
    } else {
      EXPECT_EQ(scan.counters.ground_source, GroundSource::kRunningAverageRejected) << name;
      EXPECT_EQ(pipeline.running_average_count(), before) << name;
      EXPECT_EQ(scan.ground.offset_m, average.offset_m) << name;
    }
  }
  EXPECT_GE(pipeline.running_average_count(), 1u);
}

// ---- Rendered cane-mount frames of the simulator ---------------------------------------------------

// Nearest point per bin of the noise-free depth, binned in the true U frame (gravity-aligned,
// heading of the optical axis, origin on the floor below the camera), with heights (z_min, z_max].
ObstacleScan truth_scan(const simulation::RgbdRenderer& renderer, const ImageF32& depth, const SE3& T_W_C,
                        double ground_z, const ObstaclePipelineConfig& config, double z_min, double z_max) {
  ObstacleScan truth = ObstacleScan::empty(config.scan_bins(), config.scan_min_bearing_rad, config.scan_bin_width_rad);
  const Vec3 axis = T_W_C.rotation().col(2);
  const SE3 T_W_U(Quat(Eigen::AngleAxisd(std::atan2(axis.y(), axis.x()), Vec3::UnitZ())), Vec3(T_W_C.t.x(), T_W_C.t.y(), ground_z));
  const SE3 T_U_C = T_W_U.inverse() * T_W_C;
  truth.T_U_C = T_U_C;
  for (int y = 0; y < depth.height; ++y)
    for (int x = 0; x < depth.width; ++x) {
      const float d = depth.at(x, y);
      if (!(d > 0.0f)) continue;
      const Vec3& b = renderer.bearing(x, y);
      const Vec3 p_U = T_U_C * Vec3(b * (d / b.z()));
      if (!(p_U.z() > z_min && p_U.z() <= z_max)) continue;
      const auto bin = truth.bin_of(std::atan2(p_U.y(), p_U.x()));
      const auto r = static_cast<float>(std::hypot(p_U.x(), p_U.y()));
      if (bin && r < truth.ranges[*bin]) {
        truth.ranges[*bin] = r;
        truth.nearest_U[*bin] = p_U.cast<float>();
      }
    }
  return truth;
}

struct SimulatedScanErrors {
  int frames = 0, ransac_frames = 0, bins_with_truth = 0, missed = 0, false_alarms = 0;
  double max_range_error = 0.0, max_normal_error_deg = 0.0;
  std::vector<double> range_errors;
};

// Walks `scenario_name` with the cane mount, one frame every `dt` seconds; the pipeline gets the
// noise-free depth and the nominal mount pose as prior (no gait, no sweep: the plane must fix it).
SimulatedScanErrors compare_with_simulator(const std::string& scenario_name, double dt) {
  const simulation::Scenario scenario = simulation::make_scenario(scenario_name);
  const RayCaster caster(scenario.world);
  const simulation::Mount mount = simulation::mount_preset("cane");
  simulation::WalkerConfig walker = mount.apply(simulation::WalkerConfig{});
  walker.ground_z_m = scenario.ground_z_m;
  const simulation::WalkerTrajectory trajectory(scenario.path, walker);
  const CameraCalibration calib = simulation::rescale_camera(simulation::sensor_preset(mount.default_sensor).camera, 320, 240);
  const auto camera = make_camera_model(calib);
  const simulation::RgbdRenderer renderer(caster, *camera);
  simulation::RenderOptions options;
  options.max_depth = calib.depth_max_m;
  options.render_labels = options.render_intensity = false;

  ObstaclePipelineConfig config;
  config.scan_min_bearing_rad = -40.0 * kDeg;  // the D455's 87° view
  config.scan_max_bearing_rad = 40.0 * kDeg;
  ObstaclePipeline pipeline(config);
  const SE3 prior = level_camera_T_U_C(mount.height_m + mount.t_B_C.z(), mount.camera_pitch_rad);
  const double band = 0.03;  // heights this close to the 0.1 m / 2 m limits may go either way

  SimulatedScanErrors e;
  for (double t = 1.0; t < trajectory.duration() - 0.5; t += dt) {
    const SE3 T_W_C = trajectory.state(t).T_W_B * mount.T_B_C();
    RgbdFrame frame;
    frame.depth = renderer.render(T_W_C, options).depth;
    const ObstacleScan scan = pipeline.process(camera_points_from_depth(frame, calib), prior);
    ++e.frames;
    // Facing a wall closer than the D455's 0.4 m minimum there may be nothing to fit.
    EXPECT_TRUE(scan.counters.ground_source == GroundSource::kRansac || scan.counters.after_voxel_grid < 1000u)
        << scenario_name << " t = " << t;
    e.ransac_frames += scan.counters.ground_source == GroundSource::kRansac;
    const double h = config.ransac_distance_threshold_m, top = config.above_head_height_m;
    const ObstacleScan strict = truth_scan(renderer, frame.depth, T_W_C, scenario.ground_z_m, config, h + band, top - band);
    const ObstacleScan loose = truth_scan(renderer, frame.depth, T_W_C, scenario.ground_z_m, config, h - band, top + band);
    e.max_normal_error_deg = std::max(e.max_normal_error_deg, angle_between(scan.ground.normal_C, ground_plane_of(strict.T_U_C).normal_C) / kDeg);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      // Neighbour bins: a point on a bin edge may land on either side after the fitted alignment.
      float near_loose = loose.ranges[i], far_strict = strict.ranges[i];
      for (std::size_t j = i == 0 ? 0 : i - 1; j <= std::min(scan.size() - 1, i + 1); ++j) near_loose = std::min(near_loose, loose.ranges[j]);
      if (strict.has_obstacle(i)) {
        ++e.bins_with_truth;
        if (!scan.has_obstacle(i)) {
          ++e.missed;
          continue;
        }
        // Inside [nearest loose, nearest strict]: error 0; outside, the distance to the interval.
        const double err = std::max({0.0, near_loose - static_cast<double>(scan.ranges[i]), static_cast<double>(scan.ranges[i]) - far_strict});
        e.range_errors.push_back(err);
        e.max_range_error = std::max(e.max_range_error, err);
      } else if (scan.has_obstacle(i) && !(near_loose < std::numeric_limits<float>::infinity())) {
        ++e.false_alarms;
      }
    }
  }
  return e;
}

void expect_matches_simulator(const std::string& scenario_name) {
  const SimulatedScanErrors e = compare_with_simulator(scenario_name, 0.7);
  std::vector<double> sorted = e.range_errors;
  std::sort(sorted.begin(), sorted.end());
  const double p95 = sorted.empty() ? 0.0 : sorted[sorted.size() * 95 / 100];
  ::testing::Test::RecordProperty("frames", e.frames);
  ::testing::Test::RecordProperty("bins_with_truth", e.bins_with_truth);
  ::testing::Test::RecordProperty("range_error_p95_cm", std::to_string(100 * p95));
  ::testing::Test::RecordProperty("range_error_max_cm", std::to_string(100 * e.max_range_error));
  std::printf("%s: %d frames, %d bins with obstacles, missed %d, false alarms %d, range error p95 %.1f cm max %.1f cm, "
              "normal error max %.2f deg\n", scenario_name.c_str(), e.frames, e.bins_with_truth, e.missed, e.false_alarms,
              100 * p95, 100 * e.max_range_error, e.max_normal_error_deg);
  EXPECT_GT(e.frames, 5);
  EXPECT_GE(e.ransac_frames, e.frames - 1);
  EXPECT_GT(e.bins_with_truth, 100);
  EXPECT_LT(e.max_normal_error_deg, 1.0);
  EXPECT_EQ(e.missed, 0);
  EXPECT_EQ(e.false_alarms, 0);
  EXPECT_LT(p95, 0.03);
  EXPECT_LT(e.max_range_error, 0.10);
}

TEST(ObstaclePipeline, CorridorCaneFramesMatchTheRenderedTruth) { expect_matches_simulator("corridor"); }
TEST(ObstaclePipeline, ObstacleCourseCaneFramesMatchTheRenderedTruth) { expect_matches_simulator("obstacle-course"); }

}  // namespace
}  // namespace navaid::mapping
