#pragma once
// TUM trajectory files: one pose per line, "timestamp tx ty tz qx qy qz qw" (seconds, metres,
// Hamilton quaternion with w last), blank-separated, '#' comment lines. Used for ground truth and
// for every trajectory navaid writes (run folders), and read by evo / rpg_trajectory_evaluation.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/time.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/io/text_file.hpp"

namespace navaid::io {

struct StampedPose {
  Timestamp t = 0;
  SE3 T_W_B;  ///< pose of the tracked frame in the trajectory's world frame
};

/// A quaternion whose norm is further than this from 1 is corrupt data, not rounding.
constexpr double kTumQuaternionNormTolerance = 1e-3;

/// Reads a TUM trajectory. Times may be plain decimals (exact to the nanosecond, digits past the
/// ninth rounded) or scientific notation ("1.403715524907143116e+09"). Throws IoError naming the
/// file and line on: a field count other than 8, a non-numeric / NaN / Inf field, a quaternion
/// norm outside 1 +- 1e-3, or a timestamp not strictly greater than the previous one.
std::vector<StampedPose> read_tum_trajectory(const std::filesystem::path& path);

/// Writes a "# timestamp tx ty tz qx qy qz qw" header and one line per pose: the time with exactly
/// 9 decimals (format_seconds), the 7 numbers in the shortest form that reads back to the same
/// double. Hence write -> read -> write is byte-identical. Throws IoError when the file cannot be
/// written, a value is not finite or timestamps are not strictly increasing.
void write_tum_trajectory(const std::filesystem::path& path, const std::vector<StampedPose>& poses);

/// write_tum_trajectory one pose at a time, for runs that write their trajectory as it is made
/// (the same bytes). add() throws IoError, naming the file and the pose, on the same faults;
/// close() (or the destructor, which does not throw) flushes.
class TumTrajectoryWriter {
 public:
  /// Creates (truncates) the file and writes the header; IoError when it cannot.
  explicit TumTrajectoryWriter(const std::filesystem::path& path);
  void add(const StampedPose& pose);
  /// Flushes and closes; IoError when the writes failed.
  void close();
  std::size_t poses() const { return count_; }

 private:
  std::string name_;
  std::ofstream out_;
  std::size_t count_ = 0;
  Timestamp last_t_ = 0;
};

/// One line of write_tum_trajectory, without the newline.
std::string format_tum_pose(const StampedPose& pose);

/// The trajectory as a Recording (format "tum-trajectory", poses in `groundtruth`), for
/// `navaid info` and for replaying ground truth.
Recording read_tum_trajectory_recording(const std::filesystem::path& path);

/// Parses the 8 fields of a TUM pose line (also used for TUM RGB-D groundtruth.txt); failures
/// name `file` and its current line.
StampedPose parse_tum_pose_fields(const TextFile& file, const std::vector<std::string_view>& fields);

/// Fails at `file`'s current line when the norm of `q` is further than kTumQuaternionNormTolerance
/// from 1; `columns` names its four fields in the message (e.g. "qx qy qz qw").
void require_unit_quaternion(const TextFile& file, const Quat& q, const std::string& columns);

}  // namespace navaid::io
