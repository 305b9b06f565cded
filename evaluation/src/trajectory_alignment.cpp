#include "navaid/evaluation/trajectory_alignment.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <string>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::evaluation {
namespace {

// Singular values below this fraction of the largest count as zero: the point set spans fewer
// dimensions than the rotation needs.
constexpr double kRankTolerance = 1e-10;

constexpr NameTable<AlignmentMode, 5> kModeNames{{
    {AlignmentMode::kNone, "none"},
    {AlignmentMode::kPosYaw, "4dof"},
    {AlignmentMode::kSe3, "se3"},
    {AlignmentMode::kSim3, "sim3"},
    {AlignmentMode::kScale, "scale"},
}};

Mat3 rot_z(double yaw) { return Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix(); }

Similarity align_by_one_pose(const PosePair& pair, AlignmentMode mode) {
  Similarity S;
  if (mode == AlignmentMode::kNone) return S;
  if (mode == AlignmentMode::kSim3 || mode == AlignmentMode::kScale)
    throw Error(std::string(to_string(mode)) + " alignment needs at least 2 frames (scale is undetermined by one)");
  const Mat3 R = pair.gt.rotation() * pair.est.rotation().transpose();
  // For kPosYaw the yaw maximising trace(Rz^T R), i.e. the rotation about z closest to R.
  S.R = mode == AlignmentMode::kPosYaw ? rot_z(best_yaw(R.transpose())) : R;
  S.t = pair.gt.t - S.R * pair.est.t;
  return S;
}

}  // namespace

std::string_view to_string(AlignmentMode mode) { return enum_name(kModeNames, mode, "?"); }

std::optional<AlignmentMode> alignment_mode_from_string(std::string_view name) {
  // rpg_trajectory_evaluation's name for 4dof: read, never written.
  if (name == "posyaw") return AlignmentMode::kPosYaw;
  return enum_value(kModeNames, name);
}

double best_yaw(const Mat3& K) {
  // trace(Rz(psi) K) = cos(psi) (K00 + K11) + sin(psi) (K01 - K10) + K22.
  return std::atan2(K(0, 1) - K(1, 0), K(0, 0) + K(1, 1));
}

Similarity align_positions(const std::vector<Vec3>& est, const std::vector<Vec3>& gt, AlignmentMode mode) {
  if (est.size() != gt.size())
    throw Error("alignment: " + std::to_string(est.size()) + " estimated but " + std::to_string(gt.size()) +
                " ground-truth positions");
  if (est.empty()) throw Error("alignment: no positions");
  Similarity S;
  if (mode == AlignmentMode::kNone) return S;

  const double n = static_cast<double>(est.size());
  Vec3 mu_e = Vec3::Zero(), mu_g = Vec3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) mu_e += est[i], mu_g += gt[i];
  mu_e /= n;
  mu_g /= n;
  // Sigma = 1/n sum (g - mu_g)(e - mu_e)^T; var_e = 1/n sum |e - mu_e|^2 (Umeyama eq. 38, 36).
  Mat3 Sigma = Mat3::Zero();
  double var_e = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const Vec3 de = est[i] - mu_e;
    Sigma += (gt[i] - mu_g) * de.transpose();
    var_e += de.squaredNorm();
  }
  Sigma /= n;
  var_e /= n;

  if (mode == AlignmentMode::kPosYaw) {
    const Mat3 K = Sigma.transpose();  // sum e g^T
    const double horizontal = std::hypot(K(0, 1) - K(1, 0), K(0, 0) + K(1, 1));
    double scale_of_k = 0.0;
    for (std::size_t i = 0; i < est.size(); ++i)
      scale_of_k += (est[i] - mu_e).head<2>().norm() * (gt[i] - mu_g).head<2>().norm();
    if (!(horizontal > kRankTolerance * scale_of_k) || scale_of_k == 0.0)
      throw Error("4dof alignment: the positions have no horizontal extent, so yaw is undetermined");
    S.R = rot_z(best_yaw(K));
  } else {
    const Eigen::JacobiSVD<Mat3> svd(Sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Vec3 d = svd.singularValues();
    // Scale alone is fixed by the singular values, whatever the rotation: collinear points will do.
    if (mode != AlignmentMode::kScale && !(d(1) > kRankTolerance * d(0)))
      throw Error(std::string(to_string(mode)) + " alignment: the positions are collinear (or identical), so the "
                  "rotation is undetermined; use more or other frames");
    // Reflection guard (Umeyama eq. 39-43): flip the smallest axis when U V^T is improper.
    Vec3 s(1.0, 1.0, 1.0);
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s(2) = -1.0;
    S.R = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
    if (mode == AlignmentMode::kSim3 || mode == AlignmentMode::kScale) {
      if (!(var_e > 0.0))
        throw Error(std::string(to_string(mode)) + " alignment: all estimated positions are equal, so scale is undetermined");
      S.scale = d.dot(s) / var_e;
    }
  }
  if (mode == AlignmentMode::kScale) {  // the similarity's scale only: positions are scaled about W's origin
    S.R = Mat3::Identity();
    return S;
  }
  S.t = mu_g - S.scale * S.R * mu_e;
  return S;
}

Similarity align_trajectory(const std::vector<PosePair>& pairs, AlignmentMode mode, std::size_t align_frames) {
  if (pairs.empty()) throw Error("alignment: no matched poses");
  const std::size_t n = align_frames == 0 ? pairs.size() : align_frames;
  if (n > pairs.size())
    throw Error("alignment on the first " + std::to_string(n) + " frames, but only " + std::to_string(pairs.size()) +
                " poses are matched");
  if (n == 1) return align_by_one_pose(pairs.front(), mode);
  std::vector<Vec3> est, gt;
  est.reserve(n);
  gt.reserve(n);
  for (std::size_t i = 0; i < n; ++i) est.push_back(pairs[i].est.t), gt.push_back(pairs[i].gt.t);
  return align_positions(est, gt, mode);
}

}  // namespace navaid::evaluation
