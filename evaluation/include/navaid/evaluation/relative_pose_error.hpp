#pragma once
// Relative pose error (RPE) over sub-trajectories of a given travelled length, as
// rpg_trajectory_evaluation defines it (Zhang & Scaramuzza, IROS 2018):
//  - distances along the trajectory are the cumulative path length of the matched ground truth;
//  - for every matched pose i, the end j >= i is the pose whose distance from i is closest to the
//    length L; the pair is used when that distance is within max_length_error of L (default 0.2 L);
//  - error T_err = (T_gt_i^-1 T_gt_j)^-1 (T_est_i^-1 T_est_j), the estimate's relative translation
//    multiplied by the alignment scale (1 except for Sim(3)); its translation norm [m], that norm as
//    a percentage of L, and its rotation angle.
// Relative motion does not depend on a rigid alignment, so RPE needs none (evo's RPE is the same
// quantity; evo picks j as the first pose at least L further instead of the closest).
#include <vector>

#include "navaid/evaluation/error_statistics.hpp"
#include "navaid/evaluation/time_association.hpp"

namespace navaid::evaluation {

struct RpeResult {
  double length_m = 0.0;
  std::vector<std::size_t> start, end;       ///< pair indices of each sub-trajectory
  std::vector<double> translation_errors;    ///< [m]
  std::vector<double> rotation_errors_rad;   ///< [rad]
  ErrorStatistics translation;               ///< [m]; count 0 when no sub-trajectory fits
  ErrorStatistics translation_percent;       ///< [% of length_m]
  ErrorStatistics rotation_deg;              ///< [deg]
  bool empty() const { return translation_errors.empty(); }
};

/// Cumulative path length at each position (first 0).
std::vector<double> cumulative_path_length(const std::vector<Vec3>& positions);

/// RPE at one sub-trajectory length. `scale` multiplies estimated relative translations (the Sim(3)
/// alignment's scale). A negative max_length_error means 0.2 * length. Throws navaid::Error on a
/// non-positive or non-finite length or scale. No fitting sub-trajectory gives an empty result.
RpeResult compute_rpe(const std::vector<PosePair>& pairs, double length_m, double scale = 1.0,
                      double max_length_error = -1.0);

/// Sub-trajectory lengths as percentages of a path length, truncated to centimetres (as rpg does,
/// so that the lengths print cleanly). Throws navaid::Error on percentages outside (0, 100].
std::vector<double> lengths_from_percentages(double path_length_m, const std::vector<double>& percentages);

}  // namespace navaid::evaluation
