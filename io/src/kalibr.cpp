#include "navaid/io/kalibr.hpp"

#include <algorithm>
#include <cctype>
#include <map>

#include "calibration_yaml.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::io {
namespace {

using detail::YamlFile;

CameraCalibration read_camera(const YamlFile& file, const YAML::Node& cam, const std::string& name) {
  CameraCalibration camera;
  camera.name = name;
  const auto key = [&](const std::string& k) { return detail::join_key(name, k); };

  const std::string model = detail::as_string(file, detail::require(file, cam, name, "camera_model"), key("camera_model"));
  if (model != "pinhole")
    throw ConfigError(file.path, key("camera_model"), "unsupported camera model '" + model + "' (allowed: pinhole)");
  detail::read_pinhole_intrinsics(file, detail::require(file, cam, name, "intrinsics"), key("intrinsics"), camera);
  detail::read_distortion(file, detail::require(file, cam, name, "distortion_model"), key("distortion_model"),
                          detail::require(file, cam, name, "distortion_coeffs"), key("distortion_coeffs"), camera);
  detail::read_resolution(file, detail::require(file, cam, name, "resolution"), key("resolution"), camera);

  const Eigen::Matrix4d T_cam_imu =
      detail::as_matrix4_rows(file, detail::require(file, cam, name, "T_cam_imu"), key("T_cam_imu"));
  camera.T_B_C = detail::rigid_transform(file, T_cam_imu, key("T_cam_imu")).inverse();

  // Kalibr omits the time shift when temporal calibration was not run: no shift, not an error.
  if (detail::has_key(cam, "timeshift_cam_imu"))
    camera.time_offset_s = detail::as_double(file, cam["timeshift_cam_imu"], key("timeshift_cam_imu"));
  return camera;
}

// "cam12" -> 12; -1 for any other key.
int camera_number(const std::string& key) {
  if (key.size() < 4 || key.compare(0, 3, "cam") != 0) return -1;
  const std::string digits = key.substr(3);
  if (digits.size() > 3 || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
    return -1;
  return std::stoi(digits);
}

}  // namespace

RigCalibration read_kalibr_camchain(const std::filesystem::path& path) {
  const YamlFile file(path);
  if (!file.root.IsMap())
    throw ConfigError(file.path, "<document>", "expected a map of cameras (cam0, cam1, ...)");
  std::map<int, std::string> cameras;
  for (const auto& entry : file.root) {
    if (!entry.first.IsScalar()) continue;
    const int n = camera_number(entry.first.Scalar());
    if (n >= 0) cameras.emplace(n, entry.first.Scalar());
  }
  if (cameras.empty() || cameras.begin()->first != 0) throw ConfigError(file.path, "cam0", "missing");
  RigCalibration rig;
  int expected = 0;
  for (const auto& [n, name] : cameras) {
    if (n != expected)
      throw ConfigError(file.path, "cam" + std::to_string(expected),
                        "missing (cameras must be numbered consecutively; found " + name + ")");
    rig.cameras.push_back(read_camera(file, file.root[name], name));
    ++expected;
  }
  return rig;
}

ImuCalibration read_kalibr_imu(const std::filesystem::path& path) {
  const YamlFile file(path);
  if (!file.root.IsMap()) throw ConfigError(file.path, "<document>", "expected a map of IMU parameters");
  const bool nested = detail::has_key(file.root, "imu0");
  const YAML::Node map = nested ? file.root["imu0"] : file.root;
  const std::string prefix = nested ? "imu0" : "";
  if (!map.IsMap()) throw ConfigError(file.path, prefix, "expected a map of IMU parameters");

  ImuCalibration imu;
  detail::read_imu_noise(file, map, prefix, "update_rate", imu);
  if (detail::has_key(map, "T_i_b")) {
    const std::string key = detail::join_key(prefix, "T_i_b");
    imu.T_B_I = detail::rigid_transform(file, detail::as_matrix4_rows(file, map["T_i_b"], key), key).inverse();
  }
  return imu;
}

}  // namespace navaid::io
