// The ground-aligned user frame U of the cane pipeline and its relation to the ground plane.
#include <cmath>

#include <Eigen/Geometry>

#include "navaid/mapping/obstacle_pipeline.hpp"

namespace navaid::mapping {

SE3 level_camera_T_U_C(double height_m, double pitch_down_rad) {
  // Optical frame (x right, y down, z forward) of a level camera in U (x forward, y left, z up).
  Mat3 R_level;
  R_level.col(0) = Vec3(0, -1, 0);
  R_level.col(1) = Vec3(0, 0, -1);
  R_level.col(2) = Vec3(1, 0, 0);
  // Pitching down turns the optical axis from z_C towards +y_C: a negative rotation about x_C.
  const Mat3 R_pitch = Eigen::AngleAxisd(-pitch_down_rad, Vec3::UnitX()).toRotationMatrix();
  return SE3(Mat3(R_level * R_pitch), Vec3(0, 0, height_m));
}

GroundPlane ground_plane_of(const SE3& T_U_C) {
  // z_U = r3 . p_C + t_z, with r3 the third row of R_U_C: the height above z_U = 0.
  GroundPlane g;
  g.normal_C = T_U_C.rotation().row(2).transpose();
  g.offset_m = T_U_C.t.z();
  return g;
}

namespace {
// Heading in U of the camera's optical axis (undefined when it points straight up or down).
double optical_axis_heading(const Quat& q_U_C) {
  const Vec3 z = q_U_C * Vec3::UnitZ();
  return std::atan2(z.y(), z.x());
}
}  // namespace

SE3 user_frame_from_ground(const GroundPlane& plane, const SE3& T_U_C_prior) {
  // Thesis eq. 2.5-2.8: the smallest rotation taking the normal onto the up axis.
  const Vec3 up_U = T_U_C_prior.q * plane.normal_C.normalized();
  Quat q = Quat::FromTwoVectors(up_U, Vec3::UnitZ()) * T_U_C_prior.q;
  // That rotation also turns the heading a little when the prior's roll is off (~ roll x
  // sin(pitch)); turn back about z_U so that the optical axis keeps the prior's heading, making
  // bearings independent of the prior's tilt error.
  const double yaw = optical_axis_heading(T_U_C_prior.q) - optical_axis_heading(q);
  q = Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())) * q;
  return SE3(q, Vec3(T_U_C_prior.t.x(), T_U_C_prior.t.y(), plane.offset_m));
}

}  // namespace navaid::mapping
