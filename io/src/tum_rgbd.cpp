#include "navaid/io/tum_rgbd.hpp"

#include <algorithm>
#include <string>
#include <tuple>

#include "navaid/core/errors.hpp"
#include "navaid/io/text_file.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;

struct ImageEntry {
  Timestamp t = 0;
  std::string path;
};

std::vector<ImageEntry> read_image_list(const fs::path& folder, const std::string& list_name) {
  TextFile file(folder / list_name);
  std::vector<ImageEntry> entries;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const auto fields = split_fields(line, ' ');
    require_field_count(file, fields, 2);
    ImageEntry entry;
    entry.t = parse_seconds_field(file, fields[0], "timestamp");
    require_increasing(file, entries.empty() ? 0 : entries.back().t, entry.t, !entries.empty());
    const fs::path image = folder / std::string(fields[1]);
    std::error_code ec;
    if (!fs::is_regular_file(image, ec))
      file.fail("image file '" + std::string(fields[1]) + "' does not exist (" + image.string() + ")");
    entry.path = image.string();
    entries.push_back(std::move(entry));
  }
  return entries;
}

std::vector<ImuSample> read_accelerometer(const fs::path& path) {
  TextFile file(path);
  std::vector<ImuSample> samples;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const auto fields = split_fields(line, ' ');
    require_field_count(file, fields, 4);
    ImuSample s;
    s.t = parse_seconds_field(file, fields[0], "timestamp");
    require_increasing(file, samples.empty() ? 0 : samples.back().t, s.t, !samples.empty());
    s.accel = Vec3(parse_double(file, fields[1], "ax"), parse_double(file, fields[2], "ay"),
                   parse_double(file, fields[3], "az"));
    s.has_gyro = false;
    samples.push_back(s);
  }
  return samples;
}

std::vector<GroundTruthState> read_groundtruth(const fs::path& path) {
  TextFile file(path);
  std::vector<GroundTruthState> states;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const StampedPose pose = parse_tum_pose_fields(file, split_fields(line, ' '));
    require_increasing(file, states.empty() ? 0 : states.back().t, pose.t, !states.empty());
    GroundTruthState state;
    state.t = pose.t;
    state.T_W_B = pose.T_W_B;
    states.push_back(state);
  }
  return states;
}

std::string folder_name(const fs::path& folder) {
  fs::path p = fs::absolute(folder).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p.filename().string();
}

}  // namespace

TumCamera tum_camera_from_name(std::string_view name) {
  if (name.find("freiburg1") != std::string_view::npos) return TumCamera::kFreiburg1;
  if (name.find("freiburg2") != std::string_view::npos) return TumCamera::kFreiburg2;
  if (name.find("freiburg3") != std::string_view::npos) return TumCamera::kFreiburg3;
  return TumCamera::kRosDefault;
}

CameraCalibration tum_rgbd_camera(TumCamera which) {
  CameraCalibration camera;
  camera.name = "cam0";
  camera.width = 640;
  camera.height = 480;
  camera.rate_hz = 30.0;
  // Published table (vision.in.tum.de, "Intrinsic Camera Calibration of the Kinect"); d0..d4 are
  // OpenCV's k1 k2 p1 p2 k3.
  switch (which) {
    case TumCamera::kFreiburg1:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::make_tuple(517.3, 516.5, 318.6, 255.3);
      camera.distortion = DistortionModel::kRadialTangential;
      camera.distortion_coeffs = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
      break;
    case TumCamera::kFreiburg2:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::make_tuple(520.9, 521.0, 325.1, 249.7);
      camera.distortion = DistortionModel::kRadialTangential;
      camera.distortion_coeffs = {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
      break;
    case TumCamera::kFreiburg3:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::make_tuple(535.4, 539.2, 320.1, 247.6);
      break;
    case TumCamera::kRosDefault:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::make_tuple(525.0, 525.0, 319.5, 239.5);
      break;
  }
  return camera;
}

std::vector<std::pair<std::size_t, std::size_t>> associate_nearest(const std::vector<Timestamp>& a,
                                                                   const std::vector<Timestamp>& b,
                                                                   Duration tolerance) {
  struct Candidate {
    Duration difference;
    std::size_t i, j;
  };
  std::vector<Candidate> candidates;
  std::size_t first = 0;  // first b not too early for a[i]; both inputs ascend
  for (std::size_t i = 0; i < a.size(); ++i) {
    while (first < b.size() && b[first] <= a[i] - tolerance) ++first;
    for (std::size_t j = first; j < b.size() && b[j] < a[i] + tolerance; ++j)
      candidates.push_back({a[i] > b[j] ? a[i] - b[j] : b[j] - a[i], i, j});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.difference, x.i, x.j) < std::tie(y.difference, y.i, y.j);
  });
  std::vector<bool> used_a(a.size(), false), used_b(b.size(), false);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& c : candidates) {
    if (used_a[c.i] || used_b[c.j]) continue;
    used_a[c.i] = used_b[c.j] = true;
    pairs.emplace_back(c.i, c.j);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

Recording read_tum_rgbd(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw IoError(folder.string(), "is not a folder (expected a TUM RGB-D sequence)");
  Recording recording;
  recording.path = folder.string();
  recording.format = "tum-rgbd";

  const std::string name = folder_name(folder);
  const TumCamera which = tum_camera_from_name(name);
  if (which == TumCamera::kRosDefault)
    recording.report.warn(recording.path, "folder name '" + name +
                                              "' names no freiburg1/2/3 camera: ROS default intrinsics used");
  recording.calibration.cameras.push_back(tum_rgbd_camera(which));

  const auto rgb = read_image_list(folder, "rgb.txt");
  const auto depth = read_image_list(folder, "depth.txt");
  std::vector<Timestamp> rgb_t, depth_t;
  for (const auto& e : rgb) rgb_t.push_back(e.t);
  for (const auto& e : depth) depth_t.push_back(e.t);
  const auto pairs = associate_nearest(rgb_t, depth_t, kTumAssociationTolerance);
  for (const auto& [i, j] : pairs) {
    RgbdFrame frame;
    frame.t = rgb[i].t;
    frame.index = recording.frames.size();
    frame.camera = "cam0";
    frame.intensity_path = rgb[i].path;
    frame.depth_path = depth[j].path;
    frame.depth_png_scale_m = kTumDepthPngScale;
    recording.frames.push_back(std::move(frame));
  }
  const std::string rgb_list = (folder / "rgb.txt").string();
  const std::string depth_list = (folder / "depth.txt").string();
  for (std::size_t k = pairs.size(); k < rgb.size(); ++k)
    recording.report.warn(rgb_list, "colour image without a depth image within 0.02 s: frame skipped");
  for (std::size_t k = pairs.size(); k < depth.size(); ++k)
    recording.report.warn(depth_list, "depth image without a colour image within 0.02 s: ignored");

  if (fs::exists(folder / "accelerometer.txt", ec)) recording.imu = read_accelerometer(folder / "accelerometer.txt");
  if (fs::exists(folder / "groundtruth.txt", ec)) recording.groundtruth = read_groundtruth(folder / "groundtruth.txt");
  return recording;
}

}  // namespace navaid::io
