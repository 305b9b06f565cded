// The HPnP-vs-PnP study on a small simulated feature-level recording, and its statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "estimator_fixtures.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/initialization/pose_change_study.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

PoseChangeStudySequence sequence_of(const io::Recording& rec) {
  PoseChangeStudySequence s;
  s.name = "lab";
  s.camera = rec.calibration.cameras.at(0);
  for (const auto& f : rec.features)
    if (f.camera == s.camera.name) s.frames.push_back(f);
  s.groundtruth = rec.groundtruth;
  return s;
}

const PoseChangeStudySequence& lab_walk() {
  static const PoseChangeStudySequence s = sequence_of(testing::simulate_recording(
      "pce_study", {"scenario=lab-walk-1", "mount=head", "simulation.mode=features", "duration=8", "seed=5",
                    "sensor.camera.rate=10", "features.max_per_frame=100", "features.pixel_sigma=0.5"}));
  return s;
}

TEST(PoseChangeStudy, WindowsCarryTheTruePoseChange) {
  PoseChangeStudyOptions o;
  o.gap = 5;
  o.stride = 5;
  const auto windows = make_pose_change_windows(lab_walk(), o);
  ASSERT_GE(windows.size(), 5u);
  for (const auto& w : windows) {
    EXPECT_EQ(w.frame_j, w.frame_i + 5);
    EXPECT_GE(static_cast<int>(w.correspondences.size()), o.min_correspondences);
    EXPECT_GE(w.parallax_px, o.min_parallax_px);
    // The true T_j_i is a pose change over half a second of walking: under ~1 m, not standing.
    EXPECT_GE(w.T_j_i_true.t.norm(), o.min_baseline_m);
    EXPECT_LT(w.T_j_i_true.t.norm(), 1.5);
  }
  // With all depths, both methods recover the true pose change in (nearly) every window: this
  // checks the frames, T_B_C and undistortion as much as the methods.
  int ok_hpnp = 0, ok_pnp = 0;
  o.depth_budgets = {kAllDepths};
  for (const auto& w : windows)
    for (const auto& r : evaluate_pose_change_window(w, o)) {
      EXPECT_TRUE(r.returned) << to_string(r.method) << " window " << w.index << ": " << r.reason;
      (r.method == PoseChangeMethod::kHybrid ? ok_hpnp : ok_pnp) += r.ok;
    }
  EXPECT_GE(ok_hpnp, static_cast<int>(windows.size()) - 1);
  EXPECT_GE(ok_pnp, static_cast<int>(windows.size()) - 1);
}

TEST(PoseChangeStudy, DepthBudgetsSeparateTheMethods) {
  PoseChangeStudyOptions o;
  o.gap = 5;
  o.stride = 5;
  o.depth_budgets = {2, 3, 8, kAllDepths};
  const auto windows = select_windows(make_pose_change_windows(lab_walk(), o), 6);
  ASSERT_EQ(windows.size(), 6u);
  std::vector<PoseChangeStudyRow> rows;
  for (const auto& w : windows)
    for (auto& r : evaluate_pose_change_window(w, o)) rows.push_back(r);
  ASSERT_EQ(rows.size(), 6u * 4u * 2u);
  for (const auto& r : rows) {
    if (r.budget != kAllDepths) {
      EXPECT_LE(r.depth_used, r.budget);
    }
    // PnP cannot run below 4 depth features: nullopt, never a pose.
    if (r.method == PoseChangeMethod::kPnp && r.depth_used < 4) {
      EXPECT_FALSE(r.returned);
      EXPECT_FALSE(r.ok);
    }
    if (!r.returned) {
      EXPECT_TRUE(std::isnan(r.rot_err_deg));
    }
  }
  const auto summary = summarize_pose_change_study(rows, o);
  ASSERT_EQ(summary.size(), 8u);
  EXPECT_EQ(summary[0].budget, 2);
  EXPECT_EQ(summary[0].method, PoseChangeMethod::kHybrid);
  EXPECT_EQ(summary[1].method, PoseChangeMethod::kPnp);
  EXPECT_EQ(summary[1].successes, 0);  // PnP with 2 depths
  EXPECT_EQ(summary[3].successes, 0);  // PnP with 3 depths
  // HPnP with 2-3 depths: most windows (simulated stereo depth noise makes some depths fail the
  // 1 px reprojection test, which 2-3 features cannot outvote).
  EXPECT_GE(summary[0].successes + summary[2].successes, 7);
  for (const auto& s : summary) {
    EXPECT_EQ(s.windows, 6);
    EXPECT_LE(s.wilson_low, s.success_rate);
    EXPECT_GE(s.wilson_high, s.success_rate);
  }
  std::ostringstream csv;
  write_pose_change_rows_csv(csv, rows);
  EXPECT_EQ(csv.str().rfind("window,N,method,ok,rot_err_deg,trans_err_m,inliers,depth_inliers", 0), 0u);
  EXPECT_NE(pose_change_summary_markdown(summary).find("| 2 | hpnp | 6 |"), std::string::npos);
  // Deterministic by seed.
  std::vector<PoseChangeStudyRow> again;
  for (const auto& w : windows)
    for (auto& r : evaluate_pose_change_window(w, o)) again.push_back(r);
  std::ostringstream csv2;
  write_pose_change_rows_csv(csv2, again);
  EXPECT_EQ(csv.str(), csv2.str());
}

TEST(PoseChangeStudy, WilsonIntervalKnownValues) {
  // 95 % Wilson interval of 8/10: centre (0.8 + 1.92/10)/(1 + 3.84/10), known 0.4902 .. 0.9433.
  const auto [lo, hi] = wilson_interval(8, 10);
  EXPECT_NEAR(lo, 0.4902, 1e-4);
  EXPECT_NEAR(hi, 0.9433, 1e-4);
  const auto [lo0, hi0] = wilson_interval(0, 20);
  EXPECT_DOUBLE_EQ(lo0, 0.0);
  EXPECT_NEAR(hi0, 0.1611, 1e-4);
  EXPECT_EQ(wilson_interval(0, 0), std::make_pair(0.0, 1.0));
}

TEST(PoseChangeStudy, BadOptionsAndInputThrow) {
  PoseChangeStudyOptions o;
  o.gap = 0;
  EXPECT_EQ(navaid::testing::expect_throw<ConfigError>([&] { validate(o); })->key(), "gap");
  o = {};
  o.depth_budgets = {0};
  navaid::testing::expect_throw<ConfigError>([&] { validate(o); });
  PoseChangeStudySequence s = lab_walk();
  s.groundtruth.clear();
  navaid::testing::expect_throw<Error>([&] { make_pose_change_windows(s, {}); });
}

}  // namespace
}  // namespace navaid::estimation
