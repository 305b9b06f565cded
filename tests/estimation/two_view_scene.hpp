#pragma once
// One feature seen from an anchor and a target keyframe, built with plain SE3 algebra
// (independent of the factors under test), shared by the visual-factor test files.
#include <random>

#include <Eigen/Core>

#include "factor_check.hpp"
#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation::testing {

struct TwoViews {
  double anchor[kPoseSize], target[kPoseSize], extrinsic[kPoseSize];
  double landmark[3];                  ///< [x_a, y_a, lambda] in the anchor camera
  Eigen::Vector2d m_anchor, m_target;  ///< exact observations
  double z_anchor = 0, z_target = 0;   ///< true depths

  double* lambda() { return &landmark[2]; }
  const double* lambda() const { return &landmark[2]; }
};

/// The target camera looks at the same scene from nearby; the point lies at depth [1, 6] m in the
/// anchor camera and at least 0.5 m in front of the target one.
inline TwoViews two_views(std::mt19937_64& rng) {
  for (;;) {
    const SE3 T_W_Ba = random_pose(rng);
    // Drawn last argument first: the order of record (random_draws.hpp).
    const Vec3 t_B_C = random_vector(rng, 0.1);
    const SE3 T_B_C(random_rotation(rng), t_B_C);
    const Vec3 t_Ca_Ct = random_vector(rng, 0.4);
    const SE3 T_Ca_Ct(random_rotation(rng, 0.3), t_Ca_Ct);
    const SE3 T_W_Bt = T_W_Ba * T_B_C * T_Ca_Ct * T_B_C.inverse();
    std::uniform_real_distribution<double> depth(1.0, 6.0), xy(-0.4, 0.4);
    const double z = depth(rng);
    const double x = xy(rng), y = xy(rng);
    const Vec3 P_ct = T_Ca_Ct.inverse() * Vec3(x * z, y * z, z);
    if (P_ct.z() < 0.5) continue;
    TwoViews v;
    pose_to_block(T_W_Ba, v.anchor);
    pose_to_block(T_W_Bt, v.target);
    pose_to_block(T_B_C, v.extrinsic);
    v.landmark[0] = x, v.landmark[1] = y, v.landmark[2] = 1.0 / z;
    v.m_anchor = Eigen::Vector2d(x, y);
    v.m_target = P_ct.head<2>() / P_ct.z();
    v.z_anchor = z;
    v.z_target = P_ct.z();
    return v;
  }
}

/// Moves the poses by up to ~0.05 and the inverse depth by 10 %; with `bearing`, the anchor
/// bearing by (0.01, -0.02) too.
inline void perturb(TwoViews& v, std::mt19937_64& rng, bool bearing = false) {
  for (double* block : {v.anchor, v.target, v.extrinsic}) {
    Vec6 xi;
    xi << random_vector(rng, 0.05), random_vector(rng, 0.05);
    pose_to_block(se3_boxplus(pose_from_block(block), xi), block);
  }
  v.landmark[2] *= 1.1;
  if (bearing) v.landmark[0] += 0.01, v.landmark[1] -= 0.02;
}

}  // namespace navaid::estimation::testing
