#include "navaid/experiments/start_alignment.hpp"

#include <algorithm>
#include <utility>

#include "navaid/core/errors.hpp"

namespace navaid::experiments {

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

std::vector<PoseWithCovariance> align_to_first_state(const std::vector<StateEstimate>& estimates,
                                                     const std::vector<io::StampedPose>& gt) {
  std::vector<PoseWithCovariance> out;
  if (gt.empty()) return out;
  bool have_transform = false;
  Mat3 Rz = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  for (const StateEstimate& s : estimates) {
    if (s.mode == EstimatorMode::kInitializing || s.t < gt.front().t || s.t > gt.back().t) continue;
    if (!have_transform) {
      const SE3 g = interpolate_pose(gt, s.t);
      Rz = Eigen::AngleAxisd(yaw_of(g.q) - yaw_of(s.T_W_B.q), Vec3::UnitZ()).toRotationMatrix();
      t = g.t - Rz * s.T_W_B.t;
      have_transform = true;
    }
    PoseWithCovariance p = pose_with_covariance(s);
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

}  // namespace navaid::experiments
