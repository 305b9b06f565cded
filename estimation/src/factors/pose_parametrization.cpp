#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation {

std::unique_ptr<ceres::Manifold> make_pose_manifold() { return std::make_unique<PoseManifold>(); }

void pose_to_block(const SE3& T, double* block) {
  Eigen::Map<Vec3>{block} = T.t;
  Eigen::Map<Eigen::Vector4d>{block + 3} = T.q.normalized().coeffs();
}

SE3 pose_from_block(const double* block) {
  return SE3(Quat(Eigen::Map<const Quat>(block + 3)), Vec3(Eigen::Map<const Vec3>(block)));  // SE3 normalizes q
}

SE3 enu_alignment_from_block(const double* block) {
  return SE3(Quat(Eigen::AngleAxisd(block[0], Vec3::UnitZ())), Vec3(block[1], block[2], block[3]));
}

}  // namespace navaid::estimation
