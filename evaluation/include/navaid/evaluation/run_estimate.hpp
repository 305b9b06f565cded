#pragma once
// What navaid run keeps of each estimate once it is written out: the pose, its mode, the GPS
// registration and the two 3x3 covariance blocks the NEES needs, about a sixth of a StateEstimate
// (whose 15 x 15 covariance is 1.8 KB). The rest of every estimate is streamed to estimates.csv,
// so an hour-long walk holds tens of MB of history, not hundreds.
#include <optional>

#include "navaid/core/state_estimate.hpp"
#include "navaid/evaluation/nees.hpp"

namespace navaid::evaluation {

struct RunEstimate {
  PoseWithCovariance pose;  ///< time, T_W_B and the rotation and position covariance blocks
  EstimatorMode mode = EstimatorMode::kInitializing;
  std::optional<SE3> T_ENU_W;
};

inline RunEstimate run_estimate(const StateEstimate& e) { return {pose_with_covariance(e), e.mode, e.T_ENU_W}; }

}  // namespace navaid::evaluation
