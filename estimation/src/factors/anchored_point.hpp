#pragma once
// Private helper of the visual factors: a feature anchored at its first observation, moved into
// the camera of a target keyframe, with the Jacobians every visual factor chains through.
//
//   P_ca = m_a / lambda                       (anchor camera, m_a = [x_a, y_a, 1])
//   P_w  = R_wa (R_bc P_ca + t_bc) + p_wa     (anchor body -> world)
//   P_ct = R_bc^T (R_wt^T (P_w - p_wt) - t_bc)  (world -> target body -> target camera)
//
// Jacobians are w.r.t. [dp, dtheta] with right rotation perturbations (R Exp(dtheta)), lambda and
// the anchor measurement (x_a, y_a) (the time-offset factors move the measurements).
#include "navaid/core/geometry.hpp"

namespace navaid::estimation::detail {

struct AnchoredPoint {
  Vec3 P_ct;                                  ///< point in the target camera
  Eigen::Matrix<double, 3, 6> d_anchor;       ///< d P_ct / d [dp_a, dtheta_a]
  Eigen::Matrix<double, 3, 6> d_target;       ///< d P_ct / d [dp_t, dtheta_t]
  Eigen::Matrix<double, 3, 6> d_extrinsic;    ///< d P_ct / d [dt_bc, dtheta_bc]
  Vec3 d_lambda;                              ///< d P_ct / d lambda
  Eigen::Matrix<double, 3, 2> d_m_anchor;     ///< d P_ct / d (x_a, y_a)
};

/// Parameter blocks: 7-double poses (see pose_parametrization.hpp) and the inverse depth. With
/// `with_jacobians`, every Jacobian but d_extrinsic, which needs `with_extrinsic` too (the extrinsic
/// is usually held constant, and Ceres then does not ask for it).
AnchoredPoint transfer_anchored_point(const double* pose_anchor, const double* pose_target,
                                      const double* extrinsic, double inverse_depth, const Vec3& m_anchor,
                                      bool with_jacobians, bool with_extrinsic);

}  // namespace navaid::estimation::detail
