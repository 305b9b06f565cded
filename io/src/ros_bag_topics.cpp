// Roles, drivers' presets and topics files of the ROS bag reader (no ROS headers here).
#include <array>
#include <optional>
#include <utility>

#include "calibration_yaml.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/ros_bag.hpp"

namespace navaid::io {
namespace {

using RoleMember = std::string RosBagTopics::*;
constexpr std::array<std::pair<std::string_view, RoleMember>, 9> kRoles{{
    {"imu", &RosBagTopics::imu},
    {"gyro", &RosBagTopics::gyro},
    {"accel", &RosBagTopics::accel},
    {"image", &RosBagTopics::image},
    {"depth", &RosBagTopics::depth},
    {"camera_info", &RosBagTopics::camera_info},
    {"gps", &RosBagTopics::gps},
    {"mag", &RosBagTopics::mag},
    {"groundtruth", &RosBagTopics::groundtruth},
}};

std::string role_list() {
  std::string s;
  for (const auto& [name, member] : kRoles) s += (s.empty() ? "" : ", ") + std::string(name);
  return s;
}

std::optional<RoleMember> find_role(std::string_view role) {
  for (const auto& [name, member] : kRoles)
    if (name == role) return member;
  return std::nullopt;
}

// realsense2_camera (ROS 1) with align_depth on; the IMU is united (unite_imu_method) or published
// as two topics. D435i and D455 publish the same names.
RosBagPreset realsense_preset(double baseline_m, double min_m, double max_m) {
  RosBagPreset p;
  p.roles = {{"image", {"/camera/color/image_raw", "/camera/color/image_raw/compressed"}},
             {"depth", {"/camera/aligned_depth_to_color/image_raw", "/camera/aligned_depth_to_color/image_raw/compressedDepth"}},
             {"camera_info", {"/camera/color/camera_info"}},
             {"imu", {"/camera/imu"}},
             {"gyro", {"/camera/gyro/sample"}},
             {"accel", {"/camera/accel/sample"}}};
  // Intel's D400-series datasheet: baselines 50 mm (D435i) and 95 mm (D455), ideal ranges
  // 0.3-3 m and 0.6-6 m, 0.08 px subpixel RMS.
  p.depth_baseline_m = baseline_m;
  p.depth_disparity_sigma_px = baseline_m > 0 ? 0.08 : 0.0;
  p.depth_min_m = min_m;
  p.depth_max_m = max_m;
  return p;
}

// Occipital's Structure Core ROS driver: the visible camera, depth aligned to it, IMU combined or
// as two topics.
RosBagPreset structure_core_preset() {
  RosBagPreset p;
  p.roles = {{"image", {"/visible/image_raw"}},
             {"depth", {"/depth_aligned/image"}},
             {"camera_info", {"/visible/camera_info"}},
             {"imu", {"/imu/combined"}},
             {"gyro", {"/imu/gyro"}},
             {"accel", {"/imu/accel"}}};
  return p;
}

}  // namespace

std::vector<std::string_view> ros_bag_roles() {
  std::vector<std::string_view> roles;
  for (const auto& [name, member] : kRoles) roles.push_back(name);
  return roles;
}

std::string& ros_bag_topic(RosBagTopics& topics, std::string_view role) {
  const auto member = find_role(role);
  if (!member) throw ConfigError("topics", std::string(role), "unknown role (roles: " + role_list() + ")");
  return topics.*(*member);
}

void set_ros_bag_topic(RosBagTopics& topics, std::string_view role, const std::string& topic) {
  std::string& slot = ros_bag_topic(topics, role);
  if (topic.empty()) throw ConfigError("topics", std::string(role), "the topic name is empty");
  slot = topic;
}

std::vector<std::string> ros_bag_preset_names() {
  return {"realsense", "realsense-d435i", "realsense-d455", "structure-core"};
}

RosBagPreset ros_bag_preset(const std::string& name) {
  if (name == "realsense") return realsense_preset(0.0, 0.0, 0.0);
  if (name == "realsense-d435i") return realsense_preset(0.050, 0.3, 3.0);
  if (name == "realsense-d455") return realsense_preset(0.095, 0.6, 6.0);
  if (name == "structure-core") return structure_core_preset();
  std::string names;
  for (const auto& n : ros_bag_preset_names()) names += (names.empty() ? "" : ", ") + n;
  throw ConfigError("topics", "preset", "unknown preset '" + name + "' (presets: " + names + ")");
}

RosBagTopicChoice read_ros_bag_topics_file(const std::filesystem::path& path) {
  const detail::YamlFile file(path);
  if (!file.root.IsMap()) throw ConfigError(file.path, "", "a topics file is a map: role: /topic (and preset: NAME)");
  RosBagTopicChoice choice;
  for (const auto& entry : file.root) {
    if (!entry.first.IsScalar()) throw ConfigError(file.path, "", "a key is not a name");
    const std::string key = entry.first.Scalar();
    const std::string value = detail::as_string(file, entry.second, key);
    if (key == "preset") {
      ros_bag_preset(value);  // checks the name
      choice.preset = value;
      continue;
    }
    const auto role = find_role(key);
    if (!role) throw ConfigError(file.path, key, "unknown role (roles: " + role_list() + ", preset)");
    if (value.empty()) throw ConfigError(file.path, key, "the topic name is empty");
    choice.topics.*(*role) = value;
  }
  return choice;
}

}  // namespace navaid::io
