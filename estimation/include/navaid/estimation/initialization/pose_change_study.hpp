#pragma once
// The HPnP-vs-PnP study: how often each pose-change method initializes, and how well, when the
// RGB-D camera measures few of the tracked features (far outdoor scenes).
//
// Windows are frame pairs (i, j = i + gap) of a feature-level sequence (FeatureFrame tracks with
// optional depth, ground truth T_W_B, camera calibration with T_B_C), taken every `stride` frames
// where the mean feature displacement is at least min_parallax_px (VINS' keyframe test) and the
// walker moved at least min_baseline_m (ground truth). For each
// window the common tracks form correspondences (pixels undistorted by the camera model), and for
// each depth budget N the depth of at most N features is kept (a seeded random order per window,
// so the kept sets are nested: budget 3 keeps budget 2's features). Both methods run on the same
// correspondences. Success: a pose returned with rotation error < success_rotation_deg and
// translation error < success_translation_rel x baseline + success_translation_abs_m against the
// true T_j_i = (T_W_Bj T_B_C)^-1 T_W_Bi T_B_C. Rates carry 95 % Wilson score intervals.
// `navaid init-study` (apps/cmd_init_study.cpp) runs it on recordings; docs/initialization.md.
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/estimation/initialization/pose_change.hpp"

namespace navaid::estimation {

/// Depth budget meaning "keep every measured depth".
constexpr int kAllDepths = -1;

struct PoseChangeStudyOptions {
  int gap = 10;                  ///< frames between i and j, >= 1
  int stride = 10;               ///< frames between window starts, >= 1
  double min_parallax_px = 20;   ///< mean |m_j - m_i| x focal over the common tracks, >= 0
  int min_correspondences = 20;  ///< common tracks a window needs, >= 5
  /// True baseline |t_ji| a window needs [m], >= 0: windows where the walker stands (head turns
  /// only) are not initialization windows (the estimator's still start covers them).
  double min_baseline_m = 0.05;
  std::vector<int> depth_budgets{2, 3, 4, 5, 6, 8, 10, kAllDepths};  ///< each >= 1 or kAllDepths
  double success_rotation_deg = 2.0;
  double success_translation_rel = 0.10;  ///< of the true baseline |t_ji|
  double success_translation_abs_m = 0.02;
  std::uint64_t seed = 1;  ///< depth subsets and the methods' RANSAC
  /// Method options; focal_px is replaced by the camera's (fx + fy) / 2.
  PoseChangeOptions pose_change;
};

/// Throws ConfigError naming the first bad option.
void validate(const PoseChangeStudyOptions& options, const std::string& source = "init-study");

/// One sequence: the features of one camera, its calibration and the ground truth.
struct PoseChangeStudySequence {
  std::string name;
  CameraCalibration camera;
  std::vector<FeatureFrame> frames;  ///< of this camera, time-ordered
  std::vector<GroundTruthState> groundtruth;
};

/// A frame pair with every correspondence's measured depth and the true pose change.
struct PoseChangeWindow {
  std::string sequence;
  int index = 0;           ///< position in the study, set by the caller / select_windows
  std::size_t frame_i = 0, frame_j = 0;
  Timestamp t_i = 0, t_j = 0;
  SE3 T_j_i_true;
  double focal_px = 0;
  double parallax_px = 0;
  std::vector<PoseChangeCorrespondence> correspondences;
  int depth_available = 0;
};

/// Candidate windows of a sequence (ground truth must cover them; frames outside are skipped).
/// Throws navaid::Error on unusable input (no ground truth, bad calibration).
std::vector<PoseChangeWindow> make_pose_change_windows(const PoseChangeStudySequence& sequence,
                                                       const PoseChangeStudyOptions& options);

/// At most `max_windows` of `windows`, evenly spaced (all when max_windows <= 0), renumbered.
std::vector<PoseChangeWindow> select_windows(std::vector<PoseChangeWindow> windows, int max_windows);

struct PoseChangeStudyRow {
  std::string sequence;
  int window = 0;
  Timestamp t_i = 0, t_j = 0;
  double baseline_m = 0;
  int correspondences = 0;
  int budget = kAllDepths;
  int depth_used = 0;
  PoseChangeMethod method = PoseChangeMethod::kHybrid;
  bool returned = false;  ///< the method gave a pose
  bool ok = false;        ///< and it met the success bounds
  double rot_err_deg = 0, trans_err_m = 0;  ///< NaN when not returned
  int inliers = 0, depth_inliers = 0;
  bool rotation_only = false;
  std::string reason;  ///< why the method gave no pose
};

/// Both methods x every depth budget on one window.
std::vector<PoseChangeStudyRow> evaluate_pose_change_window(const PoseChangeWindow& window,
                                                            const PoseChangeStudyOptions& options);

struct PoseChangeStudySummary {
  PoseChangeMethod method = PoseChangeMethod::kHybrid;
  int budget = kAllDepths;
  int windows = 0, returned = 0, successes = 0;
  double success_rate = 0, wilson_low = 0, wilson_high = 0;  ///< 95 %
  double median_rot_err_deg = 0, median_trans_err_m = 0;     ///< over returned poses (NaN if none)
  double mean_depth_used = 0;
};

/// One entry per (budget, method), budgets in options order.
std::vector<PoseChangeStudySummary> summarize_pose_change_study(const std::vector<PoseChangeStudyRow>& rows,
                                                                const PoseChangeStudyOptions& options);

/// 95 % Wilson score interval of k successes in n trials ([0, 1] when n = 0).
std::pair<double, double> wilson_interval(int successes, int trials, double z = 1.959963984540054);

std::string budget_label(int budget);  ///< "all" or the number
void write_pose_change_rows_csv(std::ostream& out, const std::vector<PoseChangeStudyRow>& rows);
std::string pose_change_summary_markdown(const std::vector<PoseChangeStudySummary>& summary);

}  // namespace navaid::estimation
