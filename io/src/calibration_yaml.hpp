#pragma once
// Private to navaid_io: strict yaml-cpp accessors shared by the Kalibr and EuRoC sensor.yaml
// readers. Every failure is a ConfigError naming the file and the dotted key ("cam0.T_cam_imu").
// yaml-cpp stays out of public headers; this header is not installed.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <vector>

#include "navaid/core/calibration.hpp"

namespace navaid::io::detail {

/// Rotation blocks must satisfy max|R^T R - I| <= this (and det R > 0) to count as rigid.
constexpr double kRigidTolerance = 1e-6;

/// A YAML document plus its file name for messages. Throws IoError when the file is missing and
/// IoError with the line number on a syntax error.
struct YamlFile {
  std::string path;
  YAML::Node root;
  explicit YamlFile(const std::filesystem::path& file);
};

/// The whole content of `file`, read as bytes; IoError naming `name` when it cannot be opened.
std::string read_file_text(const std::filesystem::path& file, const std::string& name);

/// `parent.key`, or "key" when parent is empty.
std::string join_key(const std::string& parent, const std::string& key);

/// The map entry `key` of `map` (whose own dotted name is `map_key`); throws when absent.
YAML::Node require(const YamlFile& file, const YAML::Node& map, const std::string& map_key,
                   const std::string& key);
/// True when `map` is a map holding `key`.
bool has_key(const YAML::Node& map, const std::string& key);

double as_double(const YamlFile& file, const YAML::Node& node, const std::string& key);
int as_int(const YamlFile& file, const YAML::Node& node, const std::string& key);
std::string as_string(const YamlFile& file, const YAML::Node& node, const std::string& key);
/// A flat sequence of finite numbers; `size` 0 accepts any length.
std::vector<double> as_doubles(const YamlFile& file, const YAML::Node& node, const std::string& key,
                               std::size_t size = 0);

/// Kalibr style: four rows of four numbers ([[..],[..],[..],[..]] or block sequence of rows).
Eigen::Matrix4d as_matrix4_rows(const YamlFile& file, const YAML::Node& node, const std::string& key);
/// EuRoC style: {rows: 4, cols: 4, data: [16 values]} or a flat sequence of 16 values, row-major.
Eigen::Matrix4d as_matrix4_flat(const YamlFile& file, const YAML::Node& node, const std::string& key);
/// Checks a homogeneous rigid transform (bottom row 0 0 0 1, orthonormal rotation, det > 0).
SE3 rigid_transform(const YamlFile& file, const Eigen::Matrix4d& m, const std::string& key);

/// Pinhole intrinsics [fu fv cu cv] with positive focal lengths.
void read_pinhole_intrinsics(const YamlFile& file, const YAML::Node& node, const std::string& key,
                             CameraCalibration& camera);
/// Resolution [width height], both positive.
void read_resolution(const YamlFile& file, const YAML::Node& node, const std::string& key,
                     CameraCalibration& camera);
/// Distortion model name (Kalibr's "radtan"/"equidistant"/"none" and EuRoC's
/// "radial-tangential") plus its coefficients, whose count must fit the model.
void read_distortion(const YamlFile& file, const YAML::Node& model_node, const std::string& model_key,
                     const YAML::Node& coeffs_node, const std::string& coeffs_key, CameraCalibration& camera);
/// Noise densities / random walks (Kalibr names) and the rate from `rate_key` under `map`.
void read_imu_noise(const YamlFile& file, const YAML::Node& map, const std::string& map_key,
                    const std::string& rate_key, ImuCalibration& imu);

}  // namespace navaid::io::detail
