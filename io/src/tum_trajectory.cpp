#include "navaid/io/tum_trajectory.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace navaid::io {
namespace {

// Renormalizing an already unit quaternion can move its last bits, which would break the
// byte-identical write -> read -> write cycle; only quaternions off by more than rounding
// (|q|^2 further than 1e-14 from 1) are renormalized.
Quat canonical_unit(const Quat& q) {
  return std::abs(q.squaredNorm() - 1.0) <= 1e-14 ? q : q.normalized();
}

std::string shortest(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace

void require_unit_quaternion(const TextFile& file, const Quat& q, const std::string& columns) {
  const double norm = q.norm();
  if (std::abs(norm - 1.0) <= kTumQuaternionNormTolerance) return;
  std::ostringstream message;
  message.precision(9);
  message << "quaternion (" << columns << ") has norm " << norm << ", not within 1e-3 of 1";
  file.fail(message.str());
}

StampedPose parse_tum_pose_fields(const TextFile& file, const std::vector<std::string_view>& fields) {
  require_field_count(file, fields, 8);
  StampedPose pose;
  pose.t = parse_seconds_field(file, fields[0], "timestamp");
  const Vec3 t(parse_double(file, fields[1], "tx"), parse_double(file, fields[2], "ty"),
               parse_double(file, fields[3], "tz"));
  const Quat q(parse_double(file, fields[7], "qw"), parse_double(file, fields[4], "qx"),
               parse_double(file, fields[5], "qy"), parse_double(file, fields[6], "qz"));
  require_unit_quaternion(file, q, "qx qy qz qw");
  pose.T_W_B.q = canonical_unit(q);
  pose.T_W_B.t = t;
  return pose;
}

std::vector<StampedPose> read_tum_trajectory(const std::filesystem::path& path) {
  TextFile file(path);
  std::vector<StampedPose> poses;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    StampedPose pose = parse_tum_pose_fields(file, split_fields(line, ' '));
    require_increasing(file, poses.empty() ? 0 : poses.back().t, pose.t, !poses.empty());
    poses.push_back(pose);
  }
  return poses;
}

std::string format_tum_pose(const StampedPose& pose) {
  const Quat q = canonical_unit(pose.T_W_B.q);
  const Vec3& t = pose.T_W_B.t;
  std::string line = format_seconds(pose.t);
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
    line += ' ';
    line += shortest(v);
  }
  return line;
}

namespace {

void check_next_pose(const std::string& name, std::size_t i, const StampedPose& p, Timestamp previous_t) {
  if (!p.T_W_B.t.allFinite() || !p.T_W_B.q.coeffs().allFinite() || p.T_W_B.q.squaredNorm() == 0.0)
    throw IoError(name, "pose " + std::to_string(i) + " at " + format_seconds(p.t) + " s has a non-finite value or a zero quaternion");
  if (i > 0 && p.t <= previous_t)
    throw IoError(name, "pose " + std::to_string(i) + ": timestamp " + format_seconds(p.t) +
                            " s is not after the previous one (" + format_seconds(previous_t) + " s)");
}

}  // namespace

void write_tum_trajectory(const std::filesystem::path& path, const std::vector<StampedPose>& poses) {
  // Everything is checked before the file is touched: a bad trajectory leaves no half file.
  for (std::size_t i = 0; i < poses.size(); ++i) check_next_pose(path.string(), i, poses[i], i > 0 ? poses[i - 1].t : 0);
  TumTrajectoryWriter writer(path);
  for (const auto& p : poses) writer.add(p);
  writer.close();
}

TumTrajectoryWriter::TumTrajectoryWriter(const std::filesystem::path& path)
    : name_(path.string()), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw IoError(name_, "cannot open for writing");
  out_ << "# timestamp tx ty tz qx qy qz qw\n";
}

void TumTrajectoryWriter::add(const StampedPose& pose) {
  check_next_pose(name_, count_, pose, last_t_);
  out_ << format_tum_pose(pose) << '\n';
  last_t_ = pose.t;
  ++count_;
}

void TumTrajectoryWriter::close() {
  out_.close();
  if (!out_) throw IoError(name_, "write failed");
}

Recording read_tum_trajectory_recording(const std::filesystem::path& path) {
  Recording recording;
  recording.path = path.string();
  recording.format = "tum-trajectory";
  for (const auto& pose : read_tum_trajectory(path)) {
    GroundTruthState state;
    state.t = pose.t;
    state.T_W_B = pose.T_W_B;
    recording.groundtruth.push_back(state);
  }
  return recording;
}

}  // namespace navaid::io
