#pragma once
// Absolute trajectory error (ATE): align the estimate to ground truth (trajectory_alignment.hpp),
// then per matched pose the position error |p_gt - S p_est| [m] and the rotation error, the angle
// of R_gt^T (R S_R R_est) [rad]. This is the ATE of Sturm et al. (TUM RGB-D) and of
// rpg_trajectory_evaluation (whose posyaw/se3/sim3 RMSE navaid reproduces to within 0.1 mm).
#include <vector>

#include "navaid/evaluation/error_statistics.hpp"
#include "navaid/evaluation/time_association.hpp"
#include "navaid/evaluation/trajectory_alignment.hpp"

namespace navaid::evaluation {

struct AteOptions {
  AlignmentMode alignment = AlignmentMode::kPosYaw;
  std::size_t align_frames = 0;  ///< align on the first N matched poses; 0 = all
};

struct AteResult {
  AlignmentMode alignment = AlignmentMode::kPosYaw;
  std::size_t align_frames = 0;  ///< number actually used
  Similarity transform;          ///< gt ~ transform * est
  std::vector<SE3> aligned;      ///< transform applied to each estimated pose
  std::vector<double> position_errors;      ///< [m], one per pair
  std::vector<double> rotation_errors_rad;  ///< [rad], one per pair
  ErrorStatistics position;      ///< [m]
  ErrorStatistics rotation_deg;  ///< [deg]
};

/// Throws navaid::Error when `pairs` is empty or the alignment is undetermined.
AteResult compute_ate(const std::vector<PosePair>& pairs, const AteOptions& options = {});

}  // namespace navaid::evaluation
