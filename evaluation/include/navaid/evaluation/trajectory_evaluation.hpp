#pragma once
// One evaluation of an estimated trajectory against ground truth, as `navaid eval` runs it:
// association (time_association.hpp), ATE after alignment (absolute_trajectory_error.hpp) and
// RPE at fixed lengths and at percentages of the matched ground truth's path length
// (relative_pose_error.hpp).
#include <vector>

#include <optional>
#include <string>

#include "navaid/evaluation/absolute_trajectory_error.hpp"
#include "navaid/evaluation/evo_conventions.hpp"
#include "navaid/evaluation/relative_pose_error.hpp"
#include "navaid/evaluation/time_association.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

struct EvaluationOptions {
  AteOptions ate;
  Duration tolerance = kDefaultAssociationTolerance;
  std::vector<double> rpe_lengths_m;                                       ///< fixed lengths
  std::vector<double> rpe_length_percent = {10.0, 20.0, 30.0, 40.0, 50.0};  ///< rpg's defaults
  std::optional<Duration> evo_max_diff;  ///< set: evo's association with this max_diff, not rpg's
  std::optional<EvoRpeOptions> evo_rpe;  ///< set: evo's RPE too, on the ATE's aligned estimate
};

struct TrajectoryEvaluation {
  std::size_t est_poses = 0;
  std::size_t gt_poses = 0;
  std::vector<PosePair> pairs;
  double gt_path_length_m = 0.0;  ///< of the matched ground truth
  AteResult ate;
  std::vector<RpeResult> rpe;  ///< fixed lengths first, then the percentages (duplicates removed)
  std::string association = "rpg";    ///< "rpg" (greedy, each pose once) or "evo"
  std::optional<EvoRpeResult> evo_rpe;
};

/// Throws navaid::Error when either trajectory is empty or no pose matches within the tolerance
/// (the message gives both time spans), and on the errors of the steps above.
TrajectoryEvaluation evaluate_trajectory(const std::vector<io::StampedPose>& est,
                                         const std::vector<io::StampedPose>& gt,
                                         const EvaluationOptions& options = {});

}  // namespace navaid::evaluation
