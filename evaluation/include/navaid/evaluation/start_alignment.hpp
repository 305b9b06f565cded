#pragma once
// An estimator that starts from a still, gravity-aligned initial state (yaw 0, position 0) has a
// world frame W that differs from the ground truth's by a 4-DOF transform (yaw about gravity +
// translation) fixed at its first state, and its covariances grow from that state. Comparing the
// estimate with the truth in that frame, and not after a best-fit alignment, is what makes NEES
// meaningful: the alignment must not absorb the drift the covariance is supposed to cover.
#include <vector>

#include "navaid/core/state_estimate.hpp"
#include "navaid/evaluation/nees.hpp"
#include "navaid/evaluation/run_estimate.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

/// Ground-truth pose at t: linear in position, slerp in orientation between the two samples
/// around t (exact at a sample). Throws navaid::Error when t lies outside the ground truth's span
/// or `gt` is not strictly increasing in time.
SE3 interpolate_pose(const std::vector<io::StampedPose>& gt, Timestamp t);

/// The 4-DOF transform T_gt_W (yaw difference about z, then translation) that puts the estimate
/// `first` exactly onto the ground truth at its time. Throws navaid::Error when first.t lies
/// outside the ground truth's span.
SE3 first_state_transform(const StateEstimate& first, const std::vector<io::StampedPose>& gt);
SE3 first_state_transform(Timestamp t, const SE3& T_W_B, const std::vector<io::StampedPose>& gt);

/// The estimates that are not initializing, expressed in the ground truth's world through the
/// 4-DOF transform that puts the first of them exactly onto the ground truth at its time: yaw
/// difference about z, then translation. Position covariances are rotated with the yaw; rotation
/// covariances (right perturbation, body frame) stay as they are. Estimates outside the ground
/// truth's time span are left out. Empty when nothing is left.
std::vector<PoseWithCovariance> align_to_first_state(const std::vector<StateEstimate>& estimates,
                                                     const std::vector<io::StampedPose>& gt);
/// The same from what navaid run keeps of its estimates.
std::vector<PoseWithCovariance> align_to_first_state(const std::vector<RunEstimate>& estimates,
                                                     const std::vector<io::StampedPose>& gt);

/// Position and orientation NEES of `aligned` (from align_to_first_state) against the
/// interpolated ground truth, with summaries (summarize_nees, dof 3).
NeesEvaluation first_state_nees(const std::vector<PoseWithCovariance>& aligned, const std::vector<io::StampedPose>& gt,
                                double confidence = 0.95);

}  // namespace navaid::evaluation
