#pragma once
// Shared by the sliding-window test files: simulated feature-level recordings made in a scratch
// folder, the estimator run over a whole recording, and interpolated ground truth.
#include <string>
#include <vector>

#include "navaid/core/state_estimate.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::estimation::testing {

/// `navaid simulate` with these `key=value` overrides (must name the scenario), read back.
io::Recording simulate_recording(const std::string& scratch_name, const std::vector<std::string>& overrides);

struct EstimatorRun {
  std::vector<StateEstimate> estimates;
  EstimatorStatistics stats;
  SE3 camera_extrinsic;  ///< T_B_C at the end (the online estimate when estimated)
  double camera_time_offset_s = 0;  ///< td at the end (the online estimate when estimated)
};

/// Every event of `rec` through a SlidingWindowEstimator configured by `overrides` (the
/// recording's geodetic origin passed on); with `flush`, the estimates of finish() appended.
EstimatorRun run_estimator(const io::Recording& rec, const std::vector<std::string>& overrides, bool flush = true);

/// Position RMSE of the estimates after the 4-DOF alignment (yaw + translation) fixed at the first
/// estimate that is not initializing (the estimator's W has yaw 0 there) [m].
double position_rmse(const std::vector<StateEstimate>& est, const std::vector<GroundTruthState>& gt);

/// Ground-truth pose at t, interpolated between the samples around it (clamped at the ends).
SE3 groundtruth_at(const std::vector<GroundTruthState>& gt, Timestamp t);

}  // namespace navaid::estimation::testing
