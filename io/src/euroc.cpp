#include "navaid/io/euroc.hpp"

#include <algorithm>

#include "calibration_yaml.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/text_file.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;
using detail::YamlFile;

SE3 read_T_BS(const YamlFile& file) {
  const Eigen::Matrix4d m = detail::as_matrix4_flat(file, detail::require(file, file.root, "", "T_BS"), "T_BS");
  return detail::rigid_transform(file, m, "T_BS");
}

std::vector<ImuSample> read_imu_csv(const fs::path& path) {
  TextFile file(path);
  std::vector<ImuSample> samples;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const auto f = split_fields(line, ',');
    require_field_count(file, f, 7);
    ImuSample s;
    s.t = parse_nanoseconds_field(file, f[0], "timestamp [ns]");
    require_increasing(file, samples.empty() ? 0 : samples.back().t, s.t, !samples.empty());
    s.gyro = Vec3(parse_double(file, f[1], "w_RS_S_x"), parse_double(file, f[2], "w_RS_S_y"),
                  parse_double(file, f[3], "w_RS_S_z"));
    s.accel = Vec3(parse_double(file, f[4], "a_RS_S_x"), parse_double(file, f[5], "a_RS_S_y"),
                   parse_double(file, f[6], "a_RS_S_z"));
    samples.push_back(s);
  }
  return samples;
}

std::vector<RgbdFrame> read_camera_csv(const fs::path& camera_dir, const std::string& name) {
  TextFile file(camera_dir / "data.csv");
  std::vector<RgbdFrame> frames;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const auto f = split_fields(line, ',');
    require_field_count(file, f, 2);
    RgbdFrame frame;
    frame.t = parse_nanoseconds_field(file, f[0], "timestamp [ns]");
    require_increasing(file, frames.empty() ? 0 : frames.back().t, frame.t, !frames.empty());
    if (f[1].empty()) file.fail("column 'filename' is empty");
    const fs::path image = camera_dir / "data" / std::string(f[1]);
    std::error_code ec;
    // A missing image means a broken copy of the data set, not a dropped frame: EuRoC lists only
    // the images it ships.
    if (!fs::is_regular_file(image, ec))
      file.fail("image file '" + std::string(f[1]) + "' does not exist (" + image.string() + ")");
    frame.index = frames.size();
    frame.camera = name;
    frame.intensity_path = image.string();
    frames.push_back(std::move(frame));
  }
  return frames;
}

std::vector<GroundTruthState> read_groundtruth_csv(const fs::path& path) {
  TextFile file(path);
  std::vector<GroundTruthState> states;
  std::string line;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    const auto f = split_fields(line, ',');
    if (f.size() != 8 && f.size() != 17)
      file.fail("expected 17 fields (or 8 for pose-only files), found " + std::to_string(f.size()) +
                " (truncated or malformed line?)");
    GroundTruthState s;
    s.t = parse_nanoseconds_field(file, f[0], "timestamp");
    require_increasing(file, states.empty() ? 0 : states.back().t, s.t, !states.empty());
    const Vec3 p(parse_double(file, f[1], "p_RS_R_x"), parse_double(file, f[2], "p_RS_R_y"),
                 parse_double(file, f[3], "p_RS_R_z"));
    const Quat q(parse_double(file, f[4], "q_RS_w"), parse_double(file, f[5], "q_RS_x"),
                 parse_double(file, f[6], "q_RS_y"), parse_double(file, f[7], "q_RS_z"));
    require_unit_quaternion(file, q, "q_RS_w q_RS_x q_RS_y q_RS_z");
    s.T_W_B = SE3(q, p);
    if (f.size() == 17) {
      s.v_W = Vec3(parse_double(file, f[8], "v_RS_R_x"), parse_double(file, f[9], "v_RS_R_y"),
                   parse_double(file, f[10], "v_RS_R_z"));
      s.b_g = Vec3(parse_double(file, f[11], "b_w_RS_S_x"), parse_double(file, f[12], "b_w_RS_S_y"),
                   parse_double(file, f[13], "b_w_RS_S_z"));
      s.b_a = Vec3(parse_double(file, f[14], "b_a_RS_S_x"), parse_double(file, f[15], "b_a_RS_S_y"),
                   parse_double(file, f[16], "b_a_RS_S_z"));
    }
    states.push_back(s);
  }
  return states;
}

fs::path find_mav0(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw IoError(folder.string(), "is not a folder (expected an EuRoC/ASL sequence)");
  if (fs::is_directory(folder / "mav0", ec)) return folder / "mav0";
  if (fs::is_directory(folder / "imu0", ec) || fs::is_directory(folder / "cam0", ec)) return folder;
  throw IoError(folder.string(), "not an EuRoC/ASL folder: no mav0/ (nor imu0/ or cam0/) inside");
}

}  // namespace

CameraCalibration read_euroc_camera_yaml(const fs::path& path, const std::string& name) {
  const YamlFile file(path);
  const YAML::Node& root = file.root;
  CameraCalibration camera;
  camera.name = name;
  camera.T_B_C = read_T_BS(file);
  const std::string model = detail::as_string(file, detail::require(file, root, "", "camera_model"), "camera_model");
  if (model != "pinhole")
    throw ConfigError(file.path, "camera_model", "unsupported camera model '" + model + "' (allowed: pinhole)");
  detail::read_pinhole_intrinsics(file, detail::require(file, root, "", "intrinsics"), "intrinsics", camera);
  detail::read_distortion(file, detail::require(file, root, "", "distortion_model"), "distortion_model",
                          detail::require(file, root, "", "distortion_coefficients"), "distortion_coefficients",
                          camera);
  detail::read_resolution(file, detail::require(file, root, "", "resolution"), "resolution", camera);
  camera.rate_hz = detail::as_double(file, detail::require(file, root, "", "rate_hz"), "rate_hz");
  if (camera.rate_hz <= 0) throw ConfigError(file.path, "rate_hz", "must be > 0");
  return camera;
}

ImuCalibration read_euroc_imu_yaml(const fs::path& path) {
  const YamlFile file(path);
  ImuCalibration imu;
  detail::read_imu_noise(file, file.root, "", "rate_hz", imu);
  imu.T_B_I = read_T_BS(file);
  return imu;
}

Recording read_euroc(const fs::path& folder, const std::optional<fs::path>& imu_calibration) {
  const fs::path mav0 = find_mav0(folder);
  Recording recording;
  recording.path = folder.string();
  recording.format = "euroc";
  std::error_code ec;
  if (!fs::is_directory(mav0 / "imu0", ec) && !fs::is_directory(mav0 / "cam0", ec))
    throw IoError(mav0.string(), "no imu0/ or cam0/ sensor folder");

  if (fs::is_directory(mav0 / "imu0", ec)) {
    recording.calibration.imu = read_euroc_imu_yaml(imu_calibration ? *imu_calibration : mav0 / "imu0" / "sensor.yaml");
    recording.imu = read_imu_csv(mav0 / "imu0" / "data.csv");
  }

  for (int n = 0;; ++n) {
    const std::string name = "cam" + std::to_string(n);
    const fs::path dir = mav0 / name;
    if (!fs::is_directory(dir, ec)) break;
    recording.calibration.cameras.push_back(read_euroc_camera_yaml(dir / "sensor.yaml", name));
    auto frames = read_camera_csv(dir, name);
    recording.frames.insert(recording.frames.end(), std::make_move_iterator(frames.begin()),
                            std::make_move_iterator(frames.end()));
  }
  // Cameras were appended in order, so a stable sort keeps cam0 before cam1 at equal times.
  std::stable_sort(recording.frames.begin(), recording.frames.end(),
                   [](const RgbdFrame& a, const RgbdFrame& b) { return a.t < b.t; });

  const fs::path gt = mav0 / "state_groundtruth_estimate0";
  if (fs::is_directory(gt, ec)) {
    // EuRoC's ground-truth "sensor" sits at the body origin (T_BS = I). Another T_BS would need the
    // angular rate to move the velocity, so it is refused rather than half applied.
    if (fs::exists(gt / "sensor.yaml", ec)) {
      const YamlFile file(gt / "sensor.yaml");
      if (!read_T_BS(file).is_approx(SE3::identity(), detail::kRigidTolerance))
        throw ConfigError(file.path, "T_BS", "ground truth must be given for the body frame (identity T_BS)");
    }
    recording.groundtruth = read_groundtruth_csv(gt / "data.csv");
  }
  return recording;
}

}  // namespace navaid::io
