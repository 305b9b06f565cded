// W-ROMA hand guidance per frame (Sec. IV), on known geometry: case I (centre from the depth
// patch, no pose needed), case II (beyond the depth range: walk towards it, bearing only), case
// III (remembered in W, mapped into the current H through the pose), arrival, and the
// uncertainty rules (case III withheld as "locating" when the pose is unsure, case I not).
#include <gtest/gtest.h>

#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/hand_guidance.hpp"
#include "navaid/simulation/apriltag_image.hpp"
#include "navaid/simulation/sensor_rig.hpp"

namespace navaid::planning {
namespace {

struct Rig {
  std::unique_ptr<CameraModel> camera;
  SE3 T_H_C;
  SE3 T_B_C;
};

Rig hand_rig() {
  CameraCalibration cal = simulation::sensor_preset("structure-core").camera;  // depth 0.3-5 m
  cal.T_B_C = simulation::mount_preset("hand").T_B_C();
  Rig r;
  r.camera = make_camera_model(cal);
  r.T_B_C = cal.T_B_C;
  r.T_H_C = SE3(Mat3::Identity(), Vec3(0.0, 0.04, -0.03));  // hand just below and behind the lens
  return r;
}

StateEstimate pose(const Vec3& p, double yaw_deg, double sigma_pos = 0.01, double sigma_rot_deg = 0.5,
                   EstimatorMode mode = EstimatorMode::kRgbdVio) {
  StateEstimate e;
  e.mode = mode;
  e.T_W_B = SE3(Quat(Eigen::AngleAxisd(deg_to_rad(yaw_deg), Vec3::UnitZ())), p);
  e.covariance = Mat15::Identity() * 1e-8;
  const double sr = deg_to_rad(sigma_rot_deg);
  e.covariance.block<3, 3>(0, 0) = Mat3::Identity() * sr * sr;
  e.covariance.block<3, 3>(3, 3) = Mat3::Identity() * sigma_pos * sigma_pos;
  return e;
}

/// A detection of the world point P_W from the estimate's (true) pose, with a flat depth patch
/// at the point's depth (or `patch_depth` when given, 0 = no depth).
TargetDetection detect_point(const Rig& rig, const StateEstimate& e, const Vec3& P_W, std::optional<double> patch_depth = {}) {
  const Vec3 P_C = (e.T_W_B * rig.T_B_C).inverse() * P_W;
  TargetDetection d;
  d.centre_px = *rig.camera->project(P_C);
  ImageF32 depth(rig.camera->width(), rig.camera->height(), 1, static_cast<float>(patch_depth.value_or(P_C.z())));
  d.depth = depth_patch_stats(depth, d.centre_px, 5, 0.3, 5.0);
  return d;
}

Vec3 truth_H(const Rig& rig, const StateEstimate& e, const Vec3& P_W) {
  return rig.T_H_C * (e.T_W_B * rig.T_B_C).inverse() * P_W;
}

TEST(DepthPatch, MedianValidCountRangeAndImageBorder) {
  ImageF32 depth(20, 10, 1, 0.0f);
  for (int v = 0; v < 10; ++v) {
    for (int u = 0; u < 20; ++u) depth.at(u, v) = 1.0f + 0.01f * static_cast<float>(u);
  }
  depth.at(10, 5) = 9.0f;  // beyond the range
  depth.at(11, 5) = 0.0f;  // no depth
  const DepthPatchStats s = depth_patch_stats(depth, Eigen::Vector2d(10.2, 4.8), 1, 0.3, 5.0);
  EXPECT_EQ(s.total, 9);
  EXPECT_EQ(s.valid, 7);
  EXPECT_NEAR(s.median_m, 1.10, 1e-6);
  const DepthPatchStats corner = depth_patch_stats(depth, Eigen::Vector2d(0, 0), 2, 0.3, 5.0);
  EXPECT_EQ(corner.total, 9);  // clipped to the image
  EXPECT_EQ(corner.valid, 9);
  EXPECT_EQ(depth_patch_stats(ImageF32(), Eigen::Vector2d(0, 0), 2, 0.3, 5.0).total, 0);
}

TEST(DepthPatch, TargetFromTagMeasuresThePatchOnlyWithDepth) {
  navaid::planning::AprilTagDetection tag;
  tag.id = 5;
  tag.centre_px = Eigen::Vector2d(10, 5);
  const auto bearing_only = navaid::planning::target_from_tag(tag, ImageF32(), 2, 0.3, 5.0);
  EXPECT_EQ(bearing_only.centre_px, tag.centre_px);
  EXPECT_FALSE(bearing_only.depth.has_value());
  const auto with_depth = navaid::planning::target_from_tag(tag, ImageF32(20, 10, 1, 2.0f), 2, 0.3, 5.0);
  ASSERT_TRUE(with_depth.depth.has_value());
  EXPECT_EQ(with_depth.depth->valid, 25);
  EXPECT_DOUBLE_EQ(with_depth.depth->median_m, 2.0);
  ASSERT_TRUE(with_depth.corners_px.has_value());
}

TEST(HandGuidance, NeverSeenIsWaitTargetNotSeen) {
  const Rig rig = hand_rig();
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const GuidanceCommand c = g.update(pose(Vec3::Zero(), 0), std::nullopt);
  EXPECT_EQ(c.action, GuidanceAction::kWait);
  EXPECT_EQ(c.reason, GuidanceReason::kTargetNotSeen);
  EXPECT_FALSE(c.hand.has_value());
}

TEST(HandGuidance, CaseICentreFromTheDepthPatchInTheHandFrame) {
  const Rig rig = hand_rig();
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const StateEstimate e = pose(Vec3(1.0, 2.0, 1.2), 30);
  // 1.5 m ahead of the body, 0.3 m to its left, 0.2 m up: up-left in the image.
  const Vec3 P_W = e.T_W_B * Vec3(1.5, 0.3, 0.2);
  const GuidanceCommand c = g.update(e, detect_point(rig, e, P_W));
  EXPECT_EQ(c.action, GuidanceAction::kGo);
  EXPECT_EQ(c.reason, GuidanceReason::kTargetInView);
  ASSERT_TRUE(c.target_H.has_value());
  EXPECT_LT((*c.target_H - truth_H(rig, e, P_W)).norm(), 1e-4);  // depth stored as float
  ASSERT_TRUE(c.hand.has_value());
  EXPECT_EQ(*c.hand, HandDirection::kUpLeft);
  EXPECT_GT(c.confidence, 0.9);
  ASSERT_TRUE(g.remembered().has_value());
  EXPECT_LT((g.remembered()->P_W - P_W).norm(), 1e-4);
}

TEST(HandGuidance, CaseIWorksWithoutAPoseButRemembersNothing) {
  const Rig rig = hand_rig();
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const StateEstimate truth = pose(Vec3::Zero(), 0);
  const Vec3 P_W(1.0, -0.3, -0.5);  // ahead, right, 16.6 deg below the optical axis (pitched 10 deg down)
  StateEstimate lost = truth;
  lost.mode = EstimatorMode::kInitializing;
  lost.covariance = Mat15::Identity() * 100.0;
  const GuidanceCommand c = g.update(lost, detect_point(rig, truth, P_W));
  EXPECT_EQ(c.reason, GuidanceReason::kTargetInView);
  ASSERT_TRUE(c.hand.has_value());
  EXPECT_EQ(*c.hand, HandDirection::kDownRight);
  EXPECT_FALSE(g.remembered().has_value());
}

TEST(HandGuidance, CaseIIBeyondTheDepthRangeWalkTowardsIt) {
  const Rig rig = hand_rig();
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const StateEstimate e = pose(Vec3::Zero(), 0);
  // 7 m along the optical axis, 1.2 m to the right: beyond the 5 m range.
  const Vec3 P_W = e.T_W_B * rig.T_B_C * Vec3(1.2, 0.0, 7.0);
  const GuidanceCommand c = g.update(e, detect_point(rig, e, P_W, 0.0));  // no depth in the patch
  EXPECT_EQ(c.action, GuidanceAction::kGo);
  EXPECT_EQ(c.reason, GuidanceReason::kTargetFar);
  EXPECT_FALSE(c.target_H.has_value());
  ASSERT_TRUE(c.heading_rad.has_value());
  // The ray in B (camera along B x, pitched 10 deg down; x_C = -y_B): (7 cos 10, -1.2, -7 sin 10).
  EXPECT_NEAR(*c.heading_rad, std::atan2(-1.2, 7.0 * std::cos(deg_to_rad(10.0))), 1e-9);  // right: negative
  ASSERT_TRUE(c.hand.has_value());
  EXPECT_EQ(*c.hand, HandDirection::kRight);
  // Straight ahead, beyond the range too: the hand is aligned, forward.
  const GuidanceCommand ahead = g.update(e, detect_point(rig, e, e.T_W_B * rig.T_B_C * Vec3(0, 0, 8.0), 8.0));
  EXPECT_EQ(ahead.reason, GuidanceReason::kTargetFar);
  EXPECT_EQ(*ahead.hand, HandDirection::kForward);
  EXPECT_FALSE(g.remembered().has_value());  // a bearing is not stored
}

TEST(HandGuidance, TooFewValidDepthPixelsIsCaseII) {
  const Rig rig = hand_rig();
  HandGuidanceConfig config;
  config.min_valid_fraction = 0.5;
  HandGuidance g(config, *rig.camera, rig.T_H_C);
  const StateEstimate e = pose(Vec3::Zero(), 0);
  TargetDetection d = detect_point(rig, e, Vec3(2.0, 0.0, 0.0));
  d.depth->valid = d.depth->total / 2 - 1;
  EXPECT_EQ(g.update(e, d).reason, GuidanceReason::kTargetFar);
  d.depth->valid = d.depth->total / 2 + 1;
  EXPECT_EQ(g.update(e, d).reason, GuidanceReason::kTargetInView);
}

TEST(HandGuidance, CaseIIIRememberedCentreThroughTheCurrentPose) {
  const Rig rig = hand_rig();
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const StateEstimate seen = pose(Vec3(0, 0, 1.2), 0);
  const Vec3 P_W = seen.T_W_B * rig.T_B_C * Vec3(0.0, 0.0, 1.5);  // on the optical axis, 1.5 m
  ASSERT_EQ(g.update(seen, detect_point(rig, seen, P_W)).hand, HandDirection::kForward);

  // The user turned 40 deg to the left and stepped aside: the bowl is out of view, to the right.
  const StateEstimate turned = pose(Vec3(0.1, 0.3, 1.2), 40);
  const GuidanceCommand c = g.update(turned, std::nullopt);
  EXPECT_EQ(c.action, GuidanceAction::kGo);
  EXPECT_EQ(c.reason, GuidanceReason::kTargetRemembered);
  ASSERT_TRUE(c.target_H.has_value());
  EXPECT_LT((*c.target_H - truth_H(rig, turned, P_W)).norm(), 1e-4);
  EXPECT_EQ(*c.hand, HandDirection::kRight);

  // Walked past it: the bowl is behind the hand's plane.
  const StateEstimate past = pose(seen.T_W_B * Vec3(2.5, 0, 0), 0);
  const GuidanceCommand b = g.update(past, std::nullopt);
  EXPECT_LT(b.target_H->z(), 0.0);
  EXPECT_EQ(*b.hand, HandDirection::kBackward);

  // The hand at the bowl, aligned: arrived.
  const Vec3 lens_W = P_W - (seen.T_W_B.q * (rig.T_B_C.q * Vec3(0, 0, 0.1)));  // 10 cm before it
  const StateEstimate at = pose(lens_W - seen.T_W_B.q * rig.T_B_C.t, 0);
  const GuidanceCommand a = g.update(at, std::nullopt);
  EXPECT_EQ(a.action, GuidanceAction::kArrived) << a.detail;
  EXPECT_EQ(a.reason, GuidanceReason::kTargetReached);
  EXPECT_EQ(*a.hand, HandDirection::kHold);
}

TEST(HandGuidance, CaseIIILocatingUnderLargeCovarianceWhileCaseIStillGuides) {
  const Rig rig = hand_rig();
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const StateEstimate seen = pose(Vec3::Zero(), 0);
  const Vec3 P_W(1.2, 0.2, 0.0);
  g.update(seen, detect_point(rig, seen, P_W));

  const GuidanceCommand heading = g.update(pose(Vec3(0.2, 0, 0), 10, 0.01, 25.0), std::nullopt);
  EXPECT_EQ(heading.action, GuidanceAction::kWait);
  EXPECT_EQ(heading.reason, GuidanceReason::kLocating);
  EXPECT_NE(heading.detail.find("heading sigma"), std::string::npos) << heading.detail;
  EXPECT_FALSE(heading.hand.has_value());

  const GuidanceCommand position = g.update(pose(Vec3(0.2, 0, 0), 10, 0.5, 0.5), std::nullopt);
  EXPECT_EQ(position.reason, GuidanceReason::kLocating);
  EXPECT_NE(position.detail.find("position sigma"), std::string::npos) << position.detail;

  const GuidanceCommand lost = g.update(pose(Vec3(0.2, 0, 0), 10, 0.01, 0.5, EstimatorMode::kLost), std::nullopt);
  EXPECT_EQ(lost.reason, GuidanceReason::kLocating);

  // The same unsure estimate with the target in view: case I guides (it needs no pose).
  const StateEstimate unsure = pose(Vec3(0.2, 0, 0), 10, 0.5, 25.0);
  const GuidanceCommand seen_now = g.update(unsure, detect_point(rig, unsure, P_W));
  EXPECT_EQ(seen_now.action, GuidanceAction::kGo);
  EXPECT_EQ(seen_now.reason, GuidanceReason::kTargetInView);

  // Stored under that estimate, nothing was gained since: case III guides again (since-seen),
  // while the absolute scope still withholds it.
  const GuidanceCommand after = g.update(pose(Vec3(0.25, 0, 0), 12, 0.5, 25.0), std::nullopt);
  EXPECT_EQ(after.reason, GuidanceReason::kTargetRemembered) << after.detail;
  HandGuidanceConfig absolute;
  absolute.scope = HandGuidanceScope::kAbsolute;
  HandGuidance ga(absolute, *rig.camera, rig.T_H_C);
  ga.update(unsure, detect_point(rig, unsure, P_W));
  EXPECT_EQ(ga.update(pose(Vec3(0.25, 0, 0), 12, 0.5, 25.0), std::nullopt).reason, GuidanceReason::kLocating);
}

TEST(HandGuidance, RememberedUncertaintyGrowsWithDepthAndGainedPoseSigma) {
  const Rig rig = hand_rig();
  const StateEstimate seen = pose(Vec3::Zero(), 0);
  HandGuidance near_g({}, *rig.camera, rig.T_H_C), far_g({}, *rig.camera, rig.T_H_C);
  near_g.update(seen, detect_point(rig, seen, Vec3(0.8, 0.0, 0.0)));
  far_g.update(seen, detect_point(rig, seen, Vec3(4.0, 0.0, 0.0)));
  EXPECT_GT(far_g.remembered()->measurement_cov_W.trace(), 10.0 * near_g.remembered()->measurement_cov_W.trace());

  // Confidence falls as the pose sigma gained since the sighting grows; the stored covariance
  // is not re-added when nothing was gained.
  const double c0 = near_g.update(pose(Vec3(0.1, 0, 0), 0, 0.01, 0.5), std::nullopt).confidence;
  const double c1 = near_g.update(pose(Vec3(0.1, 0, 0), 0, 0.05, 0.5), std::nullopt).confidence;
  const double c2 = near_g.update(pose(Vec3(0.1, 0, 0), 0, 0.10, 0.5), std::nullopt).confidence;
  EXPECT_GT(c0, 0.95);
  EXPECT_GT(c0, c1);
  EXPECT_GT(c1, c2);
  EXPECT_NEAR(c2, 1.0 - 0.1 / 0.25, 0.03);  // lateral sigma ~ the gained 0.1 m
}

TEST(HandGuidance, TagDetectionAndDepthEndToEnd) {
  // A tag on the object, drawn into the colour image with its depth, detected and guided on.
  const Rig rig = hand_rig();
  const SE3 T_C_tag(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())), Vec3(-0.15, 0.1, 0.9));
  ImageU8 gray(rig.camera->width(), rig.camera->height(), 1, 130);
  ImageF32 depth(rig.camera->width(), rig.camera->height(), 1, 0.0f);
  simulation::draw_apriltag(gray, *rig.camera, T_C_tag, 0.1, simulation::apriltag_cells("36h11", 11), 8, 4, &depth);
  AprilTagDetector detector;
  const auto tag = find_tag(detector.detect(gray), 11);
  ASSERT_TRUE(tag.has_value());
  TargetDetection d;
  d.centre_px = tag->centre_px;
  d.corners_px = tag->corners_px;
  d.depth = depth_patch_stats(depth, d.centre_px, 5, 0.3, 5.0);
  HandGuidance g({}, *rig.camera, rig.T_H_C);
  const GuidanceCommand c = g.update(pose(Vec3::Zero(), 0), d);
  EXPECT_EQ(c.reason, GuidanceReason::kTargetInView);
  EXPECT_LT((*c.target_H - rig.T_H_C * T_C_tag.t).norm(), 0.01) << c.target_H->transpose();
  EXPECT_EQ(*c.hand, HandDirection::kDownLeft);  // left (x < 0) and below (y > 0)
}

TEST(HandGuidance, ConfigKeysAreReadAndRangeChecked) {
  const HandGuidanceConfig c = read_hand_guidance_config(Config::parse(
      "planning:\n  hand:\n    patch_half_px: 7\n    max_heading_sigma_deg: 10\n    scope: absolute\n    aligned_radius_m: 0.03\n"));
  EXPECT_EQ(c.patch_half_px, 7);
  EXPECT_NEAR(c.max_heading_sigma_rad, deg_to_rad(10.0), 1e-15);
  EXPECT_EQ(c.scope, HandGuidanceScope::kAbsolute);
  EXPECT_DOUBLE_EQ(c.sector.aligned_radius_m, 0.03);
  EXPECT_THROW(read_hand_guidance_config(Config::parse("planning:\n  hand:\n    scope: relative\n")), ConfigError);
  EXPECT_THROW(read_hand_guidance_config(Config::parse("planning:\n  hand:\n    min_valid_fraction: 0\n")), ConfigError);
}

}  // namespace
}  // namespace navaid::planning
