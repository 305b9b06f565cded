#include "navaid/evaluation/trajectory_evaluation.hpp"

#include <algorithm>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {
namespace {

std::string span(const std::vector<io::StampedPose>& poses) {
  return "[" + format_seconds(poses.front().t) + ", " + format_seconds(poses.back().t) + "] s";
}

}  // namespace

TrajectoryEvaluation evaluate_trajectory(const std::vector<io::StampedPose>& est,
                                         const std::vector<io::StampedPose>& gt, const EvaluationOptions& options) {
  if (est.empty()) throw Error("evaluation: the estimated trajectory is empty");
  if (gt.empty()) throw Error("evaluation: the ground truth is empty");
  TrajectoryEvaluation e;
  e.est_poses = est.size();
  e.gt_poses = gt.size();
  const Duration tolerance = options.evo_max_diff ? *options.evo_max_diff : options.tolerance;
  e.association = options.evo_max_diff ? "evo" : "rpg";
  e.pairs = options.evo_max_diff ? associate_poses_evo(est, gt, tolerance) : associate_poses(est, gt, tolerance);
  if (e.pairs.empty())
    throw Error("evaluation: no estimated pose is within " + format_seconds(tolerance) +
                " s of a ground-truth pose (estimate spans " + span(est) + ", ground truth " + span(gt) + ")");
  std::vector<Vec3> gt_positions;
  for (const auto& p : e.pairs) gt_positions.push_back(p.gt.t);
  e.gt_path_length_m = cumulative_path_length(gt_positions).back();
  e.ate = compute_ate(e.pairs, options.ate);

  std::vector<double> lengths = options.rpe_lengths_m;
  for (const double l : lengths_from_percentages(e.gt_path_length_m, options.rpe_length_percent))
    if (l > 0.0 && std::find(lengths.begin(), lengths.end(), l) == lengths.end()) lengths.push_back(l);
  for (const double l : lengths) e.rpe.push_back(compute_rpe(e.pairs, l, e.ate.transform.scale));
  if (options.evo_rpe) e.evo_rpe = compute_rpe_evo(e.pairs, e.ate.aligned, *options.evo_rpe);
  return e;
}

}  // namespace navaid::evaluation
