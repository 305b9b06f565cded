#pragma once
// Pairing an estimated trajectory with ground truth by timestamp.
//
// Rule (the one rpg_trajectory_evaluation uses, so that ATE numbers agree with it): every
// (estimate, ground truth) pair whose times differ by strictly less than the tolerance is a
// candidate; candidates are taken greedily in order of increasing time difference (ties: lower
// estimate index, then lower ground-truth index) and a pair is kept when neither pose is used yet.
// Hence every estimate and every ground-truth pose is used at most once, and an estimate whose
// nearest ground truth went to a closer estimate may take its second-nearest one within tolerance.
// No interpolation: ground truth is usually sampled much faster (EuRoC 200 Hz) than estimates.
#include <cstddef>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/time.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

/// 0.02 s, rpg_trajectory_evaluation's default (`max_diff`).
constexpr Duration kDefaultAssociationTolerance = 20'000'000;

struct TimeMatch {
  std::size_t est = 0;  ///< index into the estimate times
  std::size_t gt = 0;   ///< index into the ground-truth times
};

/// Matches sorted by estimate index. Both inputs must be non-decreasing and the tolerance positive
/// (navaid::Error otherwise). Either input empty gives no matches.
std::vector<TimeMatch> associate_by_time(const std::vector<Timestamp>& est, const std::vector<Timestamp>& gt,
                                         Duration tolerance = kDefaultAssociationTolerance);

/// One estimated pose with the ground-truth pose matched to it.
struct PosePair {
  Timestamp t_est = 0;
  Timestamp t_gt = 0;
  SE3 est;  ///< T_W_B in the estimator's world frame
  SE3 gt;   ///< T_W_B in the ground truth's world frame
};

/// associate_by_time on the poses' times, returning the matched poses in estimate order.
std::vector<PosePair> associate_poses(const std::vector<io::StampedPose>& est, const std::vector<io::StampedPose>& gt,
                                      Duration tolerance = kDefaultAssociationTolerance);

}  // namespace navaid::evaluation
