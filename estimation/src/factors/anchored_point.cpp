#include "anchored_point.hpp"

#include "navaid/estimation/factors/pose_parametrization.hpp"

namespace navaid::estimation::detail {

AnchoredPoint transfer_anchored_point(const double* pose_anchor, const double* pose_target,
                                      const double* extrinsic, double inverse_depth, const Vec3& m_anchor,
                                      bool with_jacobians, bool with_extrinsic) {
  const SE3 T_wa = pose_from_block(pose_anchor);
  const SE3 T_wt = pose_from_block(pose_target);
  const SE3 T_bc = pose_from_block(extrinsic);
  const Mat3 R_wa = T_wa.rotation(), R_wt = T_wt.rotation(), R_bc = T_bc.rotation();

  const Vec3 P_ca = m_anchor / inverse_depth;
  const Vec3 P_ba = R_bc * P_ca + T_bc.t;
  const Vec3 P_w = R_wa * P_ba + T_wa.t;
  const Vec3 P_bt = R_wt.transpose() * (P_w - T_wt.t);
  AnchoredPoint out;
  out.P_ct = R_bc.transpose() * (P_bt - T_bc.t);
  if (!with_jacobians) return out;

  const Mat3 R_ct_w = R_bc.transpose() * R_wt.transpose();  // d P_ct / d P_w
  out.d_anchor.leftCols<3>() = R_ct_w;
  out.d_anchor.rightCols<3>() = -R_ct_w * R_wa * hat(P_ba);
  out.d_target.leftCols<3>() = -R_ct_w;
  out.d_target.rightCols<3>() = R_bc.transpose() * hat(P_bt);
  const Mat3 R_ct_ba = R_ct_w * R_wa;
  const Mat3 R_ct_ca = R_ct_ba * R_bc;
  if (with_extrinsic) {
    // T_bc enters twice: placing the point in the anchor body and leaving the target body.
    out.d_extrinsic.leftCols<3>() = R_ct_ba - R_bc.transpose();
    out.d_extrinsic.rightCols<3>() = hat(out.P_ct) - R_ct_ca * hat(P_ca);
  } else {
    out.d_extrinsic.setZero();
  }
  out.d_lambda = R_ct_ca * (-m_anchor / (inverse_depth * inverse_depth));
  out.d_m_anchor = R_ct_ca.leftCols<2>() / inverse_depth;
  return out;
}

}  // namespace navaid::estimation::detail
