#include "navaid/evaluation/start_alignment.hpp"

#include <algorithm>
#include <optional>
#include <utility>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/trajectory_alignment.hpp"

namespace navaid::evaluation {

SE3 interpolate_pose(const std::vector<io::StampedPose>& gt, Timestamp t) {
  if (gt.empty() || t < gt.front().t || t > gt.back().t)
    throw Error("interpolate_pose: time " + std::to_string(t) + " ns is outside the ground truth's span");
  const auto after = std::lower_bound(gt.begin(), gt.end(), t, [](const io::StampedPose& p, Timestamp x) { return p.t < x; });
  if (after->t == t) return after->T_W_B;
  const auto before = after - 1;
  if (!(before->t < after->t)) throw Error("interpolate_pose: ground truth times must be strictly increasing");
  const double a = static_cast<double>(t - before->t) / static_cast<double>(after->t - before->t);
  return SE3(before->T_W_B.q.slerp(a, after->T_W_B.q), (1.0 - a) * before->T_W_B.t + a * after->T_W_B.t);
}

SE3 first_state_transform(const StateEstimate& first, const std::vector<io::StampedPose>& gt) {
  return first_state_transform(first.t, first.T_W_B, gt);
}

SE3 first_state_transform(Timestamp t, const SE3& T_W_B, const std::vector<io::StampedPose>& gt) {
  const SE3 g = interpolate_pose(gt, t);
  // The rotation about z closest to taking the estimate's attitude onto the ground truth's: not
  // the difference of their Euler yaws, which near pitch +-90 deg (EuRoC's IMU has x up) turns a
  // small tilt error into degrees of yaw.
  const Mat3 Rz = Eigen::AngleAxisd(best_yaw(T_W_B.rotation() * g.rotation().transpose()), Vec3::UnitZ())
                      .toRotationMatrix();
  return SE3(Rz, Vec3(g.t - Rz * T_W_B.t));
}

std::vector<PoseWithCovariance> align_to_first_state(const std::vector<StateEstimate>& estimates,
                                                     const std::vector<io::StampedPose>& gt) {
  std::vector<RunEstimate> kept;
  kept.reserve(estimates.size());
  for (const StateEstimate& s : estimates) kept.push_back(run_estimate(s));
  return align_to_first_state(kept, gt);
}

std::vector<PoseWithCovariance> align_to_first_state(const std::vector<RunEstimate>& estimates,
                                                     const std::vector<io::StampedPose>& gt) {
  std::vector<PoseWithCovariance> out;
  if (gt.empty()) return out;
  std::optional<SE3> T_gt_W;
  Mat3 Rz = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  for (const RunEstimate& s : estimates) {
    const Timestamp ts = s.pose.t;
    if (s.mode == EstimatorMode::kInitializing || ts < gt.front().t || ts > gt.back().t) continue;
    if (!T_gt_W) {
      T_gt_W = first_state_transform(ts, s.pose.T_W_B, gt);
      Rz = T_gt_W->rotation();
      t = T_gt_W->t;
    }
    PoseWithCovariance p = s.pose;
    p.T_W_B = SE3(Mat3(Rz * p.T_W_B.rotation()), Vec3(Rz * p.T_W_B.t + t));
    p.position_covariance = Rz * p.position_covariance * Rz.transpose();
    out.push_back(p);
  }
  return out;
}

NeesEvaluation first_state_nees(const std::vector<PoseWithCovariance>& aligned, const std::vector<io::StampedPose>& gt,
                                double confidence) {
  if (aligned.empty()) throw Error("first_state_nees: no estimate to evaluate");
  std::vector<SE3> truth;
  std::vector<Timestamp> t;
  for (const auto& p : aligned) {
    truth.push_back(interpolate_pose(gt, p.t));
    t.push_back(p.t);
  }
  return nees_of_pairs(aligned, truth, std::move(t), confidence);
}

}  // namespace navaid::evaluation
