#include "navaid/io/open_input.hpp"

#include <algorithm>
#include <fstream>

#include "navaid/core/enum_names.hpp"
#include "navaid/io/euroc.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/nmea.hpp"
#include "navaid/io/ros_bag.hpp"
#include "navaid/io/text_file.hpp"
#include "navaid/io/tum_rgbd.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::io {
namespace fs = std::filesystem;

namespace {

constexpr NameTable<InputKind, 7> kNames{{
    {InputKind::kNavaidRecording, "navaid"},
    {InputKind::kEuroc, "euroc"},
    {InputKind::kTumRgbd, "tum-rgbd"},
    {InputKind::kNmeaCapture, "nmea"},
    {InputKind::kTumTrajectory, "tum-trajectory"},
    {InputKind::kRosBag, "ros-bag"},
    {InputKind::kCollection, "collection"},
}};

bool is_number(std::string_view text) {
  const std::string s(text);
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size();
}

// Looks at the first data lines only: captures can be large and binary noise may follow.
std::optional<InputKind> sniff_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string line;
  int data_lines = 0;
  while (data_lines < 40 && std::getline(in, line)) {
    if (is_blank_or_comment(line)) continue;
    ++data_lines;
    const auto t = trim(line);
    if (t.size() > 6 && t.front() == '$' && t.find(',') != std::string_view::npos) return InputKind::kNmeaCapture;
    if (data_lines == 1) {
      const auto fields = split_fields(t, ' ');
      if (fields.size() == 8 && std::all_of(fields.begin(), fields.end(), is_number)) return InputKind::kTumTrajectory;
    }
  }
  return std::nullopt;
}

bool collection_extension(const fs::path& p) {
  const auto ext = p.extension().string();
  return ext == ".log" || ext == ".nmea" || ext == ".txt" || ext == ".tum";
}

}  // namespace

std::string_view to_string(InputKind kind) { return enum_name(kNames, kind); }

std::optional<InputKind> input_kind_from_string(std::string_view name) {
  // A collection is a folder of recordings, detected only: --format does not take "collection".
  const std::optional<InputKind> kind = enum_value(kNames, name);
  if (kind == InputKind::kCollection) return std::nullopt;
  return kind;
}

std::vector<fs::path> collection_members(const fs::path& folder) {
  std::vector<fs::path> members;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || !collection_extension(entry.path())) continue;
    if (sniff_file(entry.path())) members.push_back(entry.path());
  }
  std::sort(members.begin(), members.end());
  return members;
}

InputKind detect_input(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path.string(), "does not exist");
  if (fs::is_directory(path, ec)) {
    if (fs::exists(path / "recording.yaml")) return InputKind::kNavaidRecording;
    if (fs::is_directory(path / "mav0") || (fs::is_directory(path / "imu0") && fs::is_directory(path / "cam0")))
      return InputKind::kEuroc;
    if (fs::exists(path / "rgb.txt") && fs::exists(path / "depth.txt")) return InputKind::kTumRgbd;
    if (!collection_members(path).empty()) return InputKind::kCollection;
    throw IoError(path.string(),
                  "not a recording: expected recording.yaml (navaid), mav0/ (EuRoC), rgb.txt + depth.txt "
                  "(TUM RGB-D), or NMEA capture / TUM trajectory files");
  }
  if (is_ros_bag(path)) return InputKind::kRosBag;
  if (const auto kind = sniff_file(path)) return *kind;
  throw IoError(path.string(),
                "not a recognised file: expected an NMEA 0183 capture ($..GGA/RMC lines), a TUM trajectory "
                "(timestamp tx ty tz qx qy qz qw) or a ROS 1 bag");
}

Recording read_input(const fs::path& path, std::optional<InputKind> kind) {
  const InputKind k = kind ? *kind : detect_input(path);
  switch (k) {
    case InputKind::kNavaidRecording:
      return read_navaid_recording(path);
    case InputKind::kEuroc:
      return read_euroc(path);
    case InputKind::kTumRgbd:
      return read_tum_rgbd(path);
    case InputKind::kNmeaCapture:
      return read_nmea_capture(path);
    case InputKind::kTumTrajectory:
      return read_tum_trajectory_recording(path);
    case InputKind::kRosBag:
      return read_ros_bag(path);
    case InputKind::kCollection:
      break;
  }
  throw IoError(path.string(), "is a folder of several captures or trajectories; read its members one by one");
}

Recording read_camera_recording(const std::filesystem::path& path, const std::string& what) {
  const InputKind kind = detect_input(path);
  if (kind == InputKind::kRosBag)
    throw IoError(path.string(), "is a ROS bag: convert it into a navaid recording first (navaid convert " +
                                     path.filename().string() + " OUT_DIR), then use OUT_DIR");
  if (kind != InputKind::kNavaidRecording && kind != InputKind::kEuroc && kind != InputKind::kTumRgbd)
    throw IoError(path.string(), "is a " + std::string(to_string(kind)) + ", not a recording with " + what +
                                     " (navaid, EuRoC or TUM RGB-D)");
  return read_input(path, kind);
}

}  // namespace navaid::io
