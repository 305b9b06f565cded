#pragma once
// Aligning an estimated trajectory to ground truth before absolute errors are measured: the
// transform S with p_gt ~ s R p_est + t that minimises sum |p_gt - (s R p_est + t)|^2 over the
// chosen poses (Umeyama 1991, closed form through the SVD of the cross-covariance), restricted to
//   kSe3    s = 1 (rigid),
//   kSim3   s free (monocular scale),
//   kPosYaw s = 1 and R a rotation about z (4-DOF: both world frames are gravity-aligned, so only
//           yaw and translation are unobservable for a visual-inertial estimator),
//   kScale  the scale of kSim3 alone, R = I and t = 0 (evo's --correct_scale without --align),
//   kNone   identity.
// With one pose (align_frames == 1) position alone cannot fix a rotation; the rotation is then taken
// from that pose's orientation (R = R_gt R_est^T, for kPosYaw only its yaw) and t from its position,
// as rpg_trajectory_evaluation does for its "first frame" alignment.
#include <optional>
#include <string_view>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/evaluation/time_association.hpp"

namespace navaid::evaluation {

enum class AlignmentMode { kNone, kPosYaw, kSe3, kSim3, kScale };

/// "none", "4dof", "se3", "sim3", "scale".
std::string_view to_string(AlignmentMode mode);
/// Accepts to_string's names plus "posyaw" (rpg's name for 4dof); nullopt otherwise.
std::optional<AlignmentMode> alignment_mode_from_string(std::string_view name);

/// x -> scale * R * x + t; poses: T -> (R * R_T, scale * R * p_T + t).
struct Similarity {
  double scale = 1.0;
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();

  Vec3 operator*(const Vec3& p) const { return scale * (R * p) + t; }
  SE3 apply(const SE3& T) const { return SE3(Quat(R) * T.q, *this * T.t); }
};

/// Least-squares alignment of corresponding positions, gt[i] ~ S * est[i]. Throws navaid::Error
/// when the sizes differ, a set is empty, or the points cannot determine the transform (kSe3/kSim3:
/// fewer than three non-collinear points; kPosYaw: no horizontal extent; kSim3: all estimates equal).
Similarity align_positions(const std::vector<Vec3>& est, const std::vector<Vec3>& gt, AlignmentMode mode);

/// Alignment of matched poses using the first `align_frames` pairs (0 = all of them). One frame
/// aligns by that pose (see above; kSim3 needs at least two). Throws navaid::Error on too few pairs.
Similarity align_trajectory(const std::vector<PosePair>& pairs, AlignmentMode mode, std::size_t align_frames = 0);

/// The yaw angle psi maximising trace(Rz(psi) K), i.e. the best rotation about z for the
/// cross-correlation K = sum est_i gt_i^T (centred points).
double best_yaw(const Mat3& K);

}  // namespace navaid::evaluation
