#pragma once
// Is a solved state a plausible successor of the previous estimate? (VINS-Mono's failure
// detection: implausible biases or a jump of the pose; here also a speed no walker reaches, and a
// state that is not finite.) The sliding-window estimator restarts its window from the previous
// estimate when this names a reason (docs/estimator.md, "Failure detection and recovery").
#include <cstddef>
#include <optional>
#include <string>

#include "navaid/core/state_estimate.hpp"
#include "navaid/estimation/estimator_config.hpp"

namespace navaid::estimation {

/// The newest frame's visual residual blocks after the solve, and those inside the inlier gate.
struct VisualSupport {
  std::size_t residuals = 0;
  std::size_t inliers = 0;
  /// Median inlier share of the frames of the last second before this one (1 when none).
  double recent_median = 1.0;
  double inlier_fraction() const { return residuals > 0 ? static_cast<double>(inliers) / residuals : 0.0; }
};

/// The reason `current` is implausible ("accelerometer bias 3.1 m/s^2 > 2.5", ...), or nullopt.
/// Jumps are measured against `previous` (none without it): the position against the previous
/// position moved by the previous velocity over the time between them, the rotation as the angle
/// of R_prev^T R_cur. Vision disagrees when at least min_visual_residuals blocks saw the newest
/// frame, fewer than min_inlier_fraction of them are inliers, and the recent median share was at
/// least collapse_from: a collapse. A share that stays low is a model error (a wrong calibration,
/// noise set too small) that a restart would not fix.
std::optional<std::string> detect_estimator_failure(const StateEstimate& current, const StateEstimate* previous,
                                                    const VisualSupport& support, const FailureThresholds& limits);

}  // namespace navaid::estimation
