#include "calibration_yaml.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "navaid/core/errors.hpp"

namespace navaid::io::detail {
namespace {

std::string describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a sequence";
  if (node.IsMap()) return "a map";
  return "'" + node.Scalar() + "'";
}

std::string number_text(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

YamlFile::YamlFile(const std::filesystem::path& file) : path(file.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw IoError(path, "file does not exist");
  if (std::filesystem::is_directory(file, ec)) throw IoError(path, "is a directory, expected a YAML file");
  const std::string text = read_file_text(file, path);
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw IoError(path, static_cast<std::size_t>(e.mark.line + 1), "YAML syntax error: " + e.msg);
  }
}

std::string read_file_text(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(name, "cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string join_key(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

bool has_key(const YAML::Node& map, const std::string& key) {
  return map.IsMap() && map[key].IsDefined();
}

YAML::Node require(const YamlFile& file, const YAML::Node& map, const std::string& map_key,
                   const std::string& key) {
  if (!map.IsMap())
    throw ConfigError(file.path, map_key.empty() ? "<document>" : map_key,
                      "expected a map, found " + describe(map));
  const YAML::Node value = map[key];
  if (!value.IsDefined()) throw ConfigError(file.path, join_key(map_key, key), "missing");
  return value;
}

double as_double(const YamlFile& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) throw ConfigError(file.path, key, "expected a number, found " + describe(node));
  double value = 0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(file.path, key, "expected a number, found " + describe(node));
  }
  if (!std::isfinite(value)) throw ConfigError(file.path, key, "expected a finite number, found " + describe(node));
  return value;
}

int as_int(const YamlFile& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) throw ConfigError(file.path, key, "expected an integer, found " + describe(node));
  try {
    return node.as<int>();
  } catch (const YAML::Exception&) {
    throw ConfigError(file.path, key, "expected an integer, found " + describe(node));
  }
}

std::string as_string(const YamlFile& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) throw ConfigError(file.path, key, "expected a string, found " + describe(node));
  return node.Scalar();
}

std::vector<double> as_doubles(const YamlFile& file, const YAML::Node& node, const std::string& key,
                               std::size_t size) {
  if (!node.IsSequence())
    throw ConfigError(file.path, key, "expected a sequence of numbers, found " + describe(node));
  if (size != 0 && node.size() != size)
    throw ConfigError(file.path, key,
                      "expected " + std::to_string(size) + " values, found " + std::to_string(node.size()));
  std::vector<double> values;
  values.reserve(node.size());
  for (std::size_t i = 0; i < node.size(); ++i)
    values.push_back(as_double(file, node[i], key + "[" + std::to_string(i) + "]"));
  return values;
}

Eigen::Matrix4d as_matrix4_rows(const YamlFile& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsSequence() || node.size() != 4)
    throw ConfigError(file.path, key,
                      "expected a 4x4 matrix (4 rows of 4 numbers), found " +
                          (node.IsSequence() ? std::to_string(node.size()) + " rows" : describe(node)));
  Eigen::Matrix4d m;
  for (std::size_t r = 0; r < 4; ++r) {
    const YAML::Node row = node[r];
    const std::string row_key = key + "[" + std::to_string(r) + "]";
    if (!row.IsSequence() || row.size() != 4)
      throw ConfigError(file.path, row_key,
                        "expected a row of 4 numbers of a 4x4 matrix, found " +
                            (row.IsSequence() ? std::to_string(row.size()) + " values" : describe(row)));
    for (std::size_t c = 0; c < 4; ++c)
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
          as_double(file, row[c], row_key + "[" + std::to_string(c) + "]");
  }
  return m;
}

Eigen::Matrix4d as_matrix4_flat(const YamlFile& file, const YAML::Node& node, const std::string& key) {
  YAML::Node data = node;
  std::string data_key = key;
  if (node.IsMap()) {
    const int rows = as_int(file, require(file, node, key, "rows"), key + ".rows");
    const int cols = as_int(file, require(file, node, key, "cols"), key + ".cols");
    if (rows != 4 || cols != 4)
      throw ConfigError(file.path, key,
                        "expected a 4x4 matrix, found rows: " + std::to_string(rows) + ", cols: " + std::to_string(cols));
    data = require(file, node, key, "data");
    data_key = key + ".data";
  }
  const auto values = as_doubles(file, data, data_key, 16);
  Eigen::Matrix4d m;
  for (Eigen::Index i = 0; i < 16; ++i) m(i / 4, i % 4) = values[static_cast<std::size_t>(i)];
  return m;
}

SE3 rigid_transform(const YamlFile& file, const Eigen::Matrix4d& m, const std::string& key) {
  const Eigen::RowVector4d bottom = m.row(3);
  if ((bottom - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > kRigidTolerance)
    throw ConfigError(file.path, key, "bottom row of a rigid transform must be [0, 0, 0, 1]");
  const Mat3 R = m.topLeftCorner<3, 3>();
  const double orthonormality = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality > kRigidTolerance)
    throw ConfigError(file.path, key,
                      "rotation block is not orthonormal: max |R^T R - I| = " + number_text(orthonormality) +
                          " (allowed <= 1e-6)");
  if (R.determinant() <= 0) throw ConfigError(file.path, key, "rotation block is a reflection (det R < 0)");
  return SE3(R, Vec3(m.topRightCorner<3, 1>()));
}

void read_pinhole_intrinsics(const YamlFile& file, const YAML::Node& node, const std::string& key,
                             CameraCalibration& camera) {
  const auto k = as_doubles(file, node, key, 4);
  if (k[0] <= 0 || k[1] <= 0)
    throw ConfigError(file.path, key, "focal lengths fu, fv must be > 0, found " + number_text(k[0]) + ", " + number_text(k[1]));
  camera.fx = k[0];
  camera.fy = k[1];
  camera.cx = k[2];
  camera.cy = k[3];
}

void read_resolution(const YamlFile& file, const YAML::Node& node, const std::string& key,
                     CameraCalibration& camera) {
  if (!node.IsSequence() || node.size() != 2)
    throw ConfigError(file.path, key, "expected [width, height], found " + describe(node));
  camera.width = as_int(file, node[0], key + "[0]");
  camera.height = as_int(file, node[1], key + "[1]");
  if (camera.width <= 0 || camera.height <= 0)
    throw ConfigError(file.path, key, "width and height must be > 0");
}

void read_distortion(const YamlFile& file, const YAML::Node& model_node, const std::string& model_key,
                     const YAML::Node& coeffs_node, const std::string& coeffs_key, CameraCalibration& camera) {
  const std::string model = as_string(file, model_node, model_key);
  auto coeffs = as_doubles(file, coeffs_node, coeffs_key);
  if (model == "radtan" || model == "radial-tangential") {
    if (coeffs.size() != 4 && coeffs.size() != 5)
      throw ConfigError(file.path, coeffs_key,
                        "radtan needs 4 or 5 coefficients (k1 k2 p1 p2 [k3]), found " + std::to_string(coeffs.size()));
    camera.distortion = DistortionModel::kRadialTangential;
  } else if (model == "equidistant") {
    if (coeffs.size() != 4)
      throw ConfigError(file.path, coeffs_key,
                        "equidistant needs 4 coefficients (k1 k2 k3 k4), found " + std::to_string(coeffs.size()));
    camera.distortion = DistortionModel::kEquidistant;
  } else if (model == "none") {
    for (double c : coeffs)
      if (c != 0.0) throw ConfigError(file.path, coeffs_key, "distortion model 'none' needs no or all-zero coefficients");
    coeffs.clear();
    camera.distortion = DistortionModel::kNone;
  } else {
    throw ConfigError(file.path, model_key,
                      "unsupported distortion model '" + model + "' (allowed: radtan, radial-tangential, equidistant, none)");
  }
  camera.distortion_coeffs = coeffs;
}

void read_imu_noise(const YamlFile& file, const YAML::Node& map, const std::string& map_key,
                    const std::string& rate_key, ImuCalibration& imu) {
  const auto read = [&](const std::string& key, bool zero_allowed) {
    const std::string full = join_key(map_key, key);
    const double v = as_double(file, require(file, map, map_key, key), full);
    if (v < 0 || (!zero_allowed && v == 0))
      throw ConfigError(file.path, full,
                        "must be " + std::string(zero_allowed ? ">= 0" : "> 0") + ", found " + number_text(v));
    return v;
  };
  imu.accel_noise_density = read("accelerometer_noise_density", false);
  imu.accel_random_walk = read("accelerometer_random_walk", true);
  imu.gyro_noise_density = read("gyroscope_noise_density", false);
  imu.gyro_random_walk = read("gyroscope_random_walk", true);
  imu.rate_hz = read(rate_key, false);
}

}  // namespace navaid::io::detail
