#include "navaid/io/navaid_recording.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include "calibration_yaml.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/text_file.hpp"

namespace navaid::io {
namespace fs = std::filesystem;

namespace {

// ----------------------------------------------------------------------------------------------
// File names and CSV headers (docs/recording-format.md is the contract; keep the two in step).

constexpr const char* kRecordingYaml = "recording.yaml";
constexpr const char* kCalibrationYaml = "calibration.yaml";
constexpr const char* kImuCsv = "imu.csv";
constexpr const char* kGpsCsv = "gps.csv";
constexpr const char* kMagCsv = "mag.csv";
constexpr const char* kGroundtruthCsv = "groundtruth.csv";
constexpr const char* kFramesCsv = "frames.csv";
constexpr const char* kFeaturesCsv = "features.csv";
constexpr const char* kLandmarksCsv = "landmarks.csv";
constexpr const char* kRgbDir = "rgb";
constexpr const char* kDepthDir = "depth";
constexpr const char* kLabelsDir = "labels";
constexpr const char* kConfidenceDir = "confidence";

constexpr const char* kImuHeader = "t_ns,gx,gy,gz,ax,ay,az";
constexpr const char* kGpsHeader =
    "t_ns,lat,lon,alt,geoid_sep,mode,quality,satellites,hdop,cov_ee,cov_en,cov_eu,cov_nn,cov_nu,cov_uu";
constexpr const char* kMagHeader = "t_ns,mx,my,mz";
constexpr const char* kGroundtruthHeader = "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz";
constexpr const char* kFramesHeader = "t_ns,camera,index,intensity,depth,labels,confidence";
constexpr const char* kFramesHeaderV1 = "t_ns,camera,index,intensity,depth,labels";
constexpr const char* kFeaturesHeader = "t_ns,camera,track_id,u,v,depth";
constexpr const char* kLandmarksHeader = "track_id,x,y,z";

// Sensor names of recording.yaml's `sensors` list, each with its CSV file.
struct StreamFile {
  const char* sensor;
  const char* file;
  int since_version;  // first format version that has it
};
constexpr StreamFile kStreams[] = {
    {"imu", kImuCsv, 1},
    {"frames", kFramesCsv, 1},
    {"gps", kGpsCsv, 1},
    {"mag", kMagCsv, 1},
    {"groundtruth", kGroundtruthCsv, 1},
    {"features", kFeaturesCsv, 2},
    {"landmarks", kLandmarksCsv, 2},
};
constexpr const char* kSensorList = "imu, frames, gps, mag, groundtruth, features, landmarks";

// Track ids are std::uint64_t in memory but read through the signed CSV integer parser.
constexpr long long kMaxTrackId = std::numeric_limits<long long>::max();

// A quaternion read from a file is kept bit for bit when it is unit to double precision, so that
// read-write cycles are byte-stable; renormalizing an already unit quaternion can flip last bits.
constexpr double kUnitQuaternionKeepTolerance = 1e-12;
// Beyond this the four numbers are not a rotation at all (typo, wrong column order); below it they
// are a rotation printed with few digits, which normalization repairs (same bound as TUM files).
constexpr double kUnitQuaternionRejectTolerance = 1e-3;
// A hand-written rotation matrix must be orthonormal to this (max |R^T R - I|), det +1.
constexpr double kRotationMatrixTolerance = 1e-6;

// A quaternion read from a file: kept as it is when unit to double precision, else normalized.
Quat unit_as_read(const Quat& q) {
  return std::abs(q.squaredNorm() - 1.0) <= kUnitQuaternionKeepTolerance ? q : q.normalized();
}

// GpsFix::satellites when the receiver did not say (the NMEA reader's convention).
constexpr int kUnknownSatellites = -1;

bool valid_camera_name(std::string_view name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  // YAML reads an unquoted null as "no value".
  std::string lower;
  for (const char c : name) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "null") return false;
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

// ----------------------------------------------------------------------------------------------
// Number formatting: shortest text that parses back to the same double (std::to_chars).

std::string shortest(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// YAML 1.1 parsers (PyYAML) read "1e-07" as a string; "1.0e-07" is a float everywhere.
std::string yaml_number(double value) {
  std::string text = shortest(value);
  const auto e = text.find('e');
  if (e != std::string::npos && text.find('.') == std::string::npos) text.insert(e, ".0");
  return text;
}

// ----------------------------------------------------------------------------------------------
// YAML reading: every failure is a ConfigError naming the file and the dotted key.

using detail::join_key;

struct YamlDoc {
  std::string file;
  YAML::Node root;

  explicit YamlDoc(const fs::path& path) : file(path.string()) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw IoError(file, "file does not exist");
    const std::string text = detail::read_file_text(path, file);
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw IoError(file, e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line) + 1,
                    "invalid YAML: " + e.msg);
    }
    if (!root.IsMap()) throw IoError(file, "expected a YAML map at the top level");
  }

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw ConfigError(file, key, message);
  }

  static bool present(const YAML::Node& node) { return node.IsDefined() && !node.IsNull(); }

  /// `map[name]`, or an undefined node when absent (map_key names `map` in messages).
  YAML::Node find(const YAML::Node& map, const std::string& map_key, const std::string& name) const {
    if (!map.IsMap()) fail(map_key, "must be a map");
    const YAML::Node& const_map = map;  // const lookup never inserts
    return const_map[name];
  }
  YAML::Node require(const YAML::Node& map, const std::string& map_key, const std::string& name) const {
    YAML::Node node = find(map, map_key, name);
    if (!present(node)) fail(join_key(map_key, name), "missing");
    return node;
  }

  /// Unknown keys are errors: a misspelt optional key would otherwise be silently ignored.
  void only_keys(const YAML::Node& map, const std::string& map_key, std::initializer_list<const char*> allowed) const {
    if (!map.IsMap()) fail(map_key.empty() ? "<top level>" : map_key, "must be a map");
    for (const auto& entry : map) {
      const std::string name = entry.first.Scalar();
      bool known = false;
      for (const char* a : allowed) known = known || name == a;
      if (!known) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(join_key(map_key, name), "unknown key (allowed here: " + list + ")");
      }
    }
  }

  std::string text(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(key, "must be a single value");
    return node.Scalar();
  }

  double number(const YAML::Node& node, const std::string& key) const {
    const std::string s = text(node, key);
    // from_chars: exact like strtod, but independent of the C locale's decimal separator.
    const char* first = s.data() + (!s.empty() && s[0] == '+' ? 1 : 0);
    double value = 0;
    const auto result = std::from_chars(first, s.data() + s.size(), value);
    if (s.empty() || result.ptr != s.data() + s.size() || result.ec == std::errc::invalid_argument)
      fail(key, "'" + s + "' is not a number");
    if (result.ec != std::errc() || !std::isfinite(value)) fail(key, "'" + s + "' is not a finite number");
    return value;
  }
  double number(const YAML::Node& node, const std::string& key, double min, double max) const {
    const double value = number(node, key);
    if (value < min || value > max)
      fail(key, yaml_number(value) + " is outside the allowed range [" + yaml_number(min) + ", " +
                    yaml_number(max) + "]");
    return value;
  }

  long long integer(const YAML::Node& node, const std::string& key, long long min, long long max) const {
    const std::string s = text(node, key);
    long long value = 0;
    const auto result = std::from_chars(s.data(), s.data() + s.size(), value);
    if (s.empty() || result.ec != std::errc() || result.ptr != s.data() + s.size())
      fail(key, "'" + s + "' is not an integer");
    if (value < min || value > max)
      fail(key, s + " is outside the allowed range [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    return value;
  }

  std::vector<double> numbers(const YAML::Node& node, const std::string& key, std::size_t size) const {
    if (!node.IsSequence()) fail(key, "must be a list of numbers");
    if (size > 0 && node.size() != size)
      fail(key, "must have " + std::to_string(size) + " values, found " + std::to_string(node.size()));
    std::vector<double> values;
    for (std::size_t i = 0; i < node.size(); ++i) values.push_back(number(node[i], key + "[" + std::to_string(i) + "]"));
    return values;
  }

  /// {q_wxyz: [w, x, y, z], t_m: [x, y, z]} (what the writer produces) or four rows of four
  /// numbers (a homogeneous matrix, as Kalibr prints them).
  SE3 transform(const YAML::Node& node, const std::string& key) const {
    if (node.IsSequence()) return transform_rows(node, key);
    only_keys(node, key, {"q_wxyz", "t_m"});
    const auto q = numbers(require(node, key, "q_wxyz"), join_key(key, "q_wxyz"), 4);
    const auto t = numbers(require(node, key, "t_m"), join_key(key, "t_m"), 3);
    const Quat quat(q[0], q[1], q[2], q[3]);
    const double norm = quat.norm();
    if (std::abs(norm - 1.0) > kUnitQuaternionRejectTolerance)
      fail(join_key(key, "q_wxyz"), "is not a unit quaternion (norm " + shortest(norm) + ")");
    SE3 T;
    T.q = unit_as_read(quat);
    T.t = Vec3(t[0], t[1], t[2]);
    return T;
  }

  SE3 transform_rows(const YAML::Node& node, const std::string& key) const {
    if (node.size() != 4) fail(key, "must be {q_wxyz, t_m} or four rows of four numbers");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      const auto row = numbers(node[static_cast<std::size_t>(r)], key + "[" + std::to_string(r) + "]", 4);
      for (int c = 0; c < 4; ++c) m(r, c) = row[static_cast<std::size_t>(c)];
    }
    if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
      fail(key, "bottom row must be [0, 0, 0, 1]");
    const Mat3 R = m.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() > kRotationMatrixTolerance ||
        R.determinant() <= 0)
      fail(key, "rotation block is not a rotation matrix (orthonormal, det +1)");
    return SE3(R, Vec3(m.topRightCorner<3, 1>()));
  }
};

// ----------------------------------------------------------------------------------------------
// CSV reading: exact header, exact field count, strict numbers; errors name file and line.

class CsvReader {
 public:
  CsvReader(const fs::path& path, const char* header) : file_(path) {
    for (const auto name : split_fields(header, ',')) columns_.emplace_back(name);
    std::string line;
    do {
      if (!file_.next(line)) file_.fail(std::string("missing header line '") + header + "'");
    } while (is_blank_or_comment(line));
    const auto found = split_fields(line, ',');
    if (!std::equal(found.begin(), found.end(), columns_.begin(), columns_.end()))
      file_.fail(std::string("header must be '") + header + "', found '" + printable(trim(line)) + "'");
  }

  bool next() {
    while (file_.next(line_)) {
      if (is_blank_or_comment(line_)) continue;
      fields_ = split_fields(line_, ',');
      require_field_count(file_, fields_, columns_.size());
      return true;
    }
    return false;
  }

  const TextFile& file() const { return file_; }
  [[noreturn]] void fail(const std::string& message) const { file_.fail(message); }
  std::string_view field(std::size_t i) const { return fields_[i]; }
  const std::string& column(std::size_t i) const { return columns_[i]; }
  bool empty(std::size_t i) const { return fields_[i].empty(); }

  Timestamp time() const { return parse_nanoseconds_field(file_, fields_[0], columns_[0]); }
  double number(std::size_t i) const { return parse_double(file_, fields_[i], columns_[i]); }
  double number(std::size_t i, double min, double max) const {
    const double value = number(i);
    if (value < min || value > max)
      fail("column '" + columns_[i] + "': " + std::string(fields_[i]) + " is outside [" + shortest(min) + ", " +
           shortest(max) + "]");
    return value;
  }
  /// Empty field means "unknown": NaN.
  double number_or_nan(std::size_t i) const { return empty(i) ? std::nan("") : number(i); }
  long long integer(std::size_t i, long long min, long long max) const {
    const long long value = parse_integer(file_, fields_[i], columns_[i]);
    if (value < min || value > max)
      fail("column '" + columns_[i] + "': " + std::string(fields_[i]) + " is outside [" + std::to_string(min) +
           ", " + std::to_string(max) + "]");
    return value;
  }
  Vec3 vec3(std::size_t i) const {
    // Sequenced, so that the first bad column is the one reported.
    const double x = number(i);
    const double y = number(i + 1);
    const double z = number(i + 2);
    return Vec3(x, y, z);
  }
  /// Three columns that are either all empty (nullopt) or all numbers.
  std::optional<Vec3> optional_vec3(std::size_t i) const {
    const int blanks = int{empty(i)} + int{empty(i + 1)} + int{empty(i + 2)};
    if (blanks == 3) return std::nullopt;
    if (blanks != 0)
      fail("columns '" + columns_[i] + "," + columns_[i + 1] + "," + columns_[i + 2] +
           "' must be all set or all empty");
    return vec3(i);
  }

  /// time(), which must be after the previous call's (streams whose rows share one clock).
  Timestamp increasing_time() {
    const Timestamp t = time();
    io::require_increasing(file_, previous_t_, t, has_previous_t_);
    previous_t_ = t;
    has_previous_t_ = true;
    return t;
  }

 private:
  TextFile file_;
  std::vector<std::string> columns_;
  std::string line_;
  std::vector<std::string_view> fields_;
  Timestamp previous_t_ = 0;
  bool has_previous_t_ = false;
};

void read_imu(const fs::path& path, Recording& rec) {
  CsvReader csv(path, kImuHeader);
  while (csv.next()) {
    ImuSample s;
    s.t = csv.increasing_time();
    const auto gyro = csv.optional_vec3(1);
    s.has_gyro = gyro.has_value();
    s.gyro = gyro.value_or(Vec3::Zero());
    s.accel = csv.vec3(4);
    rec.imu.push_back(s);
  }
}

void read_gps(const fs::path& path, Recording& rec) {
  CsvReader csv(path, kGpsHeader);
  while (csv.next()) {
    GpsFix f;
    f.t = csv.increasing_time();
    f.latitude_deg = csv.number(1, -90, 90);
    f.longitude_deg = csv.number(2, -180, 180);
    f.altitude_m = csv.number_or_nan(3);
    f.geoid_separation_m = csv.number_or_nan(4);
    f.mode = static_cast<GpsFixMode>(csv.integer(5, 1, 3));
    f.quality = static_cast<int>(csv.integer(6, 0, 9));
    f.satellites = csv.empty(7) ? kUnknownSatellites : static_cast<int>(csv.integer(7, 0, 1000));
    f.hdop = csv.empty(8) ? std::nan("") : csv.number(8, 0, 1e9);
    const double ee = csv.number(9, 0, 1e18), en = csv.number(10), eu = csv.number(11);
    const double nn = csv.number(12, 0, 1e18), nu = csv.number(13), uu = csv.number(14, 0, 1e18);
    f.covariance_enu << ee, en, eu, en, nn, nu, eu, nu, uu;
    rec.gps.push_back(f);
  }
}

void read_mag(const fs::path& path, Recording& rec) {
  CsvReader csv(path, kMagHeader);
  while (csv.next()) {
    MagSample s;
    s.t = csv.increasing_time();
    s.field = csv.vec3(1);
    rec.mag.push_back(s);
  }
}

void read_groundtruth(const fs::path& path, Recording& rec) {
  CsvReader csv(path, kGroundtruthHeader);
  while (csv.next()) {
    GroundTruthState g;
    g.t = csv.increasing_time();
    g.T_W_B.t = csv.vec3(1);
    const double qw = csv.number(4);
    const double qx = csv.number(5);
    const double qy = csv.number(6);
    const double qz = csv.number(7);
    const Quat q(qw, qx, qy, qz);
    if (std::abs(q.norm() - 1.0) > kUnitQuaternionRejectTolerance)
      csv.fail("quaternion (qw,qx,qy,qz) has norm " + shortest(q.norm()) + ", not 1");
    g.T_W_B.q = unit_as_read(q);
    g.v_W = csv.optional_vec3(8);
    g.b_g = csv.optional_vec3(11);
    g.b_a = csv.optional_vec3(14);
    rec.groundtruth.push_back(g);
  }
}

// A frame's image path: relative, inside the recording, and the file must exist.
std::string frame_image_path(const CsvReader& csv, const fs::path& folder, std::size_t column) {
  const std::string_view text = csv.field(column);
  if (text.empty()) return {};
  const fs::path relative{std::string(text)};
  const std::string what = "column '" + csv.column(column) + "': '" + std::string(text) + "'";
  if (relative.is_absolute() || relative.has_root_name())
    csv.fail(what + " must be a path relative to the recording folder");
  for (const auto& part : relative)
    if (part == "..") csv.fail(what + " must stay inside the recording folder (no '..')");
  const fs::path full = folder / relative;
  std::error_code ec;
  if (!fs::is_regular_file(full, ec)) csv.fail(what + ": image file " + full.string() + " does not exist");
  return full.string();
}

void read_frames(const fs::path& path, const fs::path& folder, int version, Recording& rec) {
  CsvReader csv(path, version >= 2 ? kFramesHeader : kFramesHeaderV1);
  std::set<std::string> calibrated;
  for (const auto& c : rec.calibration.cameras) calibrated.insert(c.name);
  std::map<std::string, Timestamp> last_of_camera;
  Timestamp previous_row = 0;
  bool has_previous_row = false;
  while (csv.next()) {
    RgbdFrame f;
    f.t = csv.time();
    f.camera = std::string(csv.field(1));
    if (!valid_camera_name(f.camera))
      csv.fail("column 'camera': '" + f.camera + "' is not a valid camera name (letter, then letters, digits, _ or -)");
    if (has_previous_row && f.t < previous_row)
      csv.fail("rows must be in time order: t_ns " + std::to_string(f.t) + " after " + std::to_string(previous_row));
    auto [last, first_of_camera] = last_of_camera.try_emplace(f.camera, f.t);
    io::require_increasing(csv.file(), last->second, f.t, !first_of_camera);
    last->second = f.t;
    previous_row = f.t;
    has_previous_row = true;
    f.index = static_cast<std::uint64_t>(csv.integer(2, 0, std::numeric_limits<long long>::max()));
    f.intensity_path = frame_image_path(csv, folder, 3);
    f.depth_path = frame_image_path(csv, folder, 4);
    f.labels_path = frame_image_path(csv, folder, 5);
    if (version >= 2) {
      f.confidence_path = frame_image_path(csv, folder, 6);
      if (!f.confidence_path.empty() && f.labels_path.empty())
        csv.fail("column 'confidence': a label confidence needs labels (column 'labels' is empty)");
    }
    f.depth_png_scale_m = kNavaidDepthScaleM;
    if (!calibrated.count(f.camera))
      rec.report.warn(path.string(), "frames of camera '" + f.camera + "', which calibration.yaml does not list");
    rec.frames.push_back(std::move(f));
  }
}

void read_features(const fs::path& path, Recording& rec) {
  CsvReader csv(path, kFeaturesHeader);
  std::set<std::string> calibrated;
  for (const auto& c : rec.calibration.cameras) calibrated.insert(c.name);
  std::map<std::string, Timestamp> last_of_camera;
  bool marker_frame = false;  // the current frame is a "no features" marker row
  while (csv.next()) {
    const Timestamp t = csv.time();
    const std::string camera(csv.field(1));
    if (!valid_camera_name(camera))
      csv.fail("column 'camera': '" + camera + "' is not a valid camera name (letter, then letters, digits, _ or -)");
    const bool same_frame =
        !rec.features.empty() && rec.features.back().t == t && rec.features.back().camera == camera;
    if (!same_frame) {
      if (!rec.features.empty() && t < rec.features.back().t)
        csv.fail("rows must be in time order: t_ns " + std::to_string(t) + " after " +
                 std::to_string(rec.features.back().t));
      const auto [last, first_of_camera] = last_of_camera.try_emplace(camera, t);
      if (!first_of_camera && last->second == t)  // earlier times are caught by the row order
        csv.fail("camera '" + camera + "' has a second frame at t_ns " + std::to_string(t) +
                 " (the rows of one frame must be consecutive)");
      last->second = t;
      if (!calibrated.count(camera))
        rec.report.warn(path.string(), "features of camera '" + camera + "', which calibration.yaml does not list");
      FeatureFrame frame;
      frame.t = t;
      frame.camera = camera;
      rec.features.push_back(std::move(frame));
      marker_frame = false;
    }
    FeatureFrame& frame = rec.features.back();
    const bool marker = csv.empty(2) && csv.empty(3) && csv.empty(4) && csv.empty(5);
    if (marker || marker_frame) {
      if (same_frame)
        csv.fail("a row with empty track_id, u, v and depth marks a frame without features and must be the only "
                 "row of its frame");
      marker_frame = true;
      continue;
    }
    FeatureObservation obs;
    obs.track_id = static_cast<std::uint64_t>(csv.integer(2, 0, kMaxTrackId));
    if (!frame.features.empty() && obs.track_id <= frame.features.back().track_id)
      csv.fail("column 'track_id': " + std::to_string(obs.track_id) + " after " +
               std::to_string(frame.features.back().track_id) +
               " in the same frame (track ids must be strictly increasing within a frame, no duplicates)");
    const double u = csv.number(3);
    const double v = csv.number(4);
    obs.uv = Eigen::Vector2d(u, v);
    if (!csv.empty(5)) {
      const double depth = csv.number(5);
      if (!(depth > 0))
        csv.fail("column 'depth': " + std::string(csv.field(5)) +
                 " must be positive (leave the field empty when there is no depth)");
      obs.depth_m = depth;
    }
    frame.features.push_back(obs);
  }
}

void read_landmarks(const fs::path& path, Recording& rec) {
  CsvReader csv(path, kLandmarksHeader);
  while (csv.next()) {
    Landmark l;
    l.id = static_cast<std::uint64_t>(csv.integer(0, 0, kMaxTrackId));
    if (!rec.landmarks.empty() && l.id <= rec.landmarks.back().id)
      csv.fail("column 'track_id': " + std::to_string(l.id) + " after " + std::to_string(rec.landmarks.back().id) +
               " (track ids must be strictly increasing)");
    l.p_W = csv.vec3(1);
    rec.landmarks.push_back(l);
  }
}

// ----------------------------------------------------------------------------------------------
// YAML files.

// Returns the format version.
int read_recording_yaml(const fs::path& path, Recording& rec, std::set<std::string>& sensors) {
  const YamlDoc doc(path);
  const std::string format = doc.text(doc.require(doc.root, "", "format"), "format");
  if (format != kNavaidFormatName)
    doc.fail("format", "'" + format + "' is not a navaid recording (expected '" + kNavaidFormatName + "')");
  // Version before any other key: a newer file must fail with "unsupported version", not with
  // a confusing complaint about a key that version added or renamed.
  const long long version = doc.integer(doc.require(doc.root, "", "version"), "version", 0,
                                        std::numeric_limits<int>::max());
  if (version < kNavaidOldestVersion || version > kNavaidFormatVersion)
    doc.fail("version", "unsupported navaid recording version " + std::to_string(version) +
                            "; this build reads versions " + std::to_string(kNavaidOldestVersion) + " to " +
                            std::to_string(kNavaidFormatVersion));
  doc.only_keys(doc.root, "", {"format", "version", "sensors", "origin"});

  const YAML::Node list = doc.require(doc.root, "", "sensors");
  if (!list.IsSequence()) doc.fail("sensors", std::string("must be a list of sensors among ") + kSensorList);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = "sensors[" + std::to_string(i) + "]";
    const std::string name = doc.text(list[i], key);
    const auto* stream = std::find_if(std::begin(kStreams), std::end(kStreams),
                                      [&](const StreamFile& s) { return name == s.sensor; });
    if (stream == std::end(kStreams)) doc.fail(key, "unknown sensor '" + name + "' (allowed: " + kSensorList + ")");
    if (stream->since_version > version)
      doc.fail(key, "sensor '" + name + "' needs format version " + std::to_string(stream->since_version) +
                        " (the file says version " + std::to_string(version) + ")");
    if (!sensors.insert(name).second) doc.fail(key, "sensor '" + name + "' is listed twice");
  }

  const YAML::Node origin = doc.find(doc.root, "", "origin");
  if (YamlDoc::present(origin)) {
    doc.only_keys(origin, "origin", {"latitude_deg", "longitude_deg", "height_m"});
    GeodeticOrigin o;
    o.latitude_deg = doc.number(doc.require(origin, "origin", "latitude_deg"), "origin.latitude_deg", -90, 90);
    o.longitude_deg = doc.number(doc.require(origin, "origin", "longitude_deg"), "origin.longitude_deg", -180, 180);
    o.height_m = doc.number(doc.require(origin, "origin", "height_m"), "origin.height_m");
    rec.origin = o;
  }
  return static_cast<int>(version);
}

constexpr double kHuge = 1e300;

CameraCalibration read_camera(const YamlDoc& doc, const YAML::Node& node, const std::string& key) {
  doc.only_keys(node, key,
                {"name", "resolution", "intrinsics", "distortion_model", "distortion_coeffs", "T_B_C",
                 "time_offset_s", "rate_hz", "depth"});
  CameraCalibration c;
  c.name = doc.text(doc.require(node, key, "name"), join_key(key, "name"));
  if (!valid_camera_name(c.name))
    doc.fail(join_key(key, "name"), "'" + c.name + "' is not a valid camera name (letter, then letters, digits, _ or -)");

  const std::string res_key = join_key(key, "resolution");
  const YAML::Node res = doc.require(node, key, "resolution");
  if (!res.IsSequence() || res.size() != 2) doc.fail(res_key, "must be [width, height]");
  c.width = static_cast<int>(doc.integer(res[0], res_key + "[0]", 1, 100000));
  c.height = static_cast<int>(doc.integer(res[1], res_key + "[1]", 1, 100000));

  const std::string k_key = join_key(key, "intrinsics");
  const auto k = doc.numbers(doc.require(node, key, "intrinsics"), k_key, 4);
  if (!(k[0] > 0 && k[1] > 0)) doc.fail(k_key, "focal lengths fx, fy must be positive");
  c.fx = k[0];
  c.fy = k[1];
  c.cx = k[2];
  c.cy = k[3];

  const std::string model_key = join_key(key, "distortion_model");
  const std::string model = doc.text(doc.require(node, key, "distortion_model"), model_key);
  const std::string coeffs_key = join_key(key, "distortion_coeffs");
  c.distortion_coeffs = doc.numbers(doc.require(node, key, "distortion_coeffs"), coeffs_key, 0);
  const std::size_t n = c.distortion_coeffs.size();
  if (model == "none") {
    c.distortion = DistortionModel::kNone;
    if (n != 0) doc.fail(coeffs_key, "must be [] for distortion_model none");
  } else if (model == "radtan") {
    c.distortion = DistortionModel::kRadialTangential;
    if (n != 4 && n != 5) doc.fail(coeffs_key, "radtan takes 4 or 5 values [k1, k2, p1, p2(, k3)]");
  } else if (model == "equidistant") {
    c.distortion = DistortionModel::kEquidistant;
    if (n != 4) doc.fail(coeffs_key, "equidistant takes 4 values [k1, k2, k3, k4]");
  } else {
    doc.fail(model_key, "'" + model + "' is not one of none, radtan, equidistant");
  }

  c.T_B_C = doc.transform(doc.require(node, key, "T_B_C"), join_key(key, "T_B_C"));
  c.time_offset_s = doc.number(doc.require(node, key, "time_offset_s"), join_key(key, "time_offset_s"), -1e6, 1e6);
  c.rate_hz = doc.number(doc.require(node, key, "rate_hz"), join_key(key, "rate_hz"), 0, 1e6);

  const std::string depth_key = join_key(key, "depth");
  const YAML::Node depth = doc.find(node, key, "depth");
  if (YamlDoc::present(depth)) {
    doc.only_keys(depth, depth_key, {"min_m", "max_m", "baseline_m", "disparity_sigma_px"});
    const auto get = [&](const char* name) {
      return doc.number(doc.require(depth, depth_key, name), join_key(depth_key, name), 0, kHuge);
    };
    c.depth_min_m = get("min_m");
    c.depth_max_m = get("max_m");
    c.depth_baseline_m = get("baseline_m");
    c.depth_disparity_sigma_px = get("disparity_sigma_px");
    if (c.depth_max_m < c.depth_min_m) doc.fail(join_key(depth_key, "max_m"), "must not be below min_m");
  }
  return c;
}

RigCalibration read_calibration_yaml(const fs::path& path) {
  const YamlDoc doc(path);
  doc.only_keys(doc.root, "", {"cameras", "imu", "gps", "mag"});
  RigCalibration rig;

  const YAML::Node cameras = doc.require(doc.root, "", "cameras");
  if (!cameras.IsSequence()) doc.fail("cameras", "must be a list (use [] for none)");
  std::set<std::string> names;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const std::string key = "cameras[" + std::to_string(i) + "]";
    rig.cameras.push_back(read_camera(doc, cameras[i], key));
    if (!names.insert(rig.cameras.back().name).second)
      doc.fail(join_key(key, "name"), "camera '" + rig.cameras.back().name + "' is listed twice");
  }

  const YAML::Node imu = doc.find(doc.root, "", "imu");
  if (YamlDoc::present(imu)) {
    doc.only_keys(imu, "imu",
                  {"rate_hz", "gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
                   "accelerometer_random_walk", "T_B_I"});
    ImuCalibration c;
    const auto get = [&](const char* name, double min) {
      return doc.number(doc.require(imu, "imu", name), join_key("imu", name), min, kHuge);
    };
    c.rate_hz = get("rate_hz", 0);
    c.gyro_noise_density = get("gyroscope_noise_density", 0);
    c.gyro_random_walk = get("gyroscope_random_walk", 0);
    c.accel_noise_density = get("accelerometer_noise_density", 0);
    c.accel_random_walk = get("accelerometer_random_walk", 0);
    const YAML::Node T = doc.find(imu, "imu", "T_B_I");
    if (YamlDoc::present(T)) c.T_B_I = doc.transform(T, "imu.T_B_I");
    rig.imu = c;
  }

  const YAML::Node gps = doc.find(doc.root, "", "gps");
  if (YamlDoc::present(gps)) {
    doc.only_keys(gps, "gps", {"lever_arm_B_m", "rate_hz"});
    const auto arm = doc.numbers(doc.require(gps, "gps", "lever_arm_B_m"), "gps.lever_arm_B_m", 3);
    rig.gps_lever_arm_B = Vec3(arm[0], arm[1], arm[2]);
    const YAML::Node rate = doc.find(gps, "gps", "rate_hz");
    if (YamlDoc::present(rate)) rig.gps_rate_hz = doc.number(rate, "gps.rate_hz", 0, 1e6);
  }

  const YAML::Node mag = doc.find(doc.root, "", "mag");
  if (YamlDoc::present(mag)) {
    doc.only_keys(mag, "mag", {"rate_hz"});
    rig.mag_rate_hz = doc.number(doc.require(mag, "mag", "rate_hz"), "mag.rate_hz", 0, 1e6);
  }
  return rig;
}

// ----------------------------------------------------------------------------------------------
// Writing.

// Builds CSV text, refusing values the reader would reject (so a written recording always reads).
class CsvWriter {
 public:
  CsvWriter(const fs::path& path, const char* header) : file_(path.string()) {
    for (const auto name : split_fields(header, ',')) columns_.emplace_back(name);
    text_ = std::string(header) + "\n";
  }

  /// Starts a row whose first field is the time stamp.
  void begin_row(Timestamp t, std::size_t sample) {
    begin_row(sample);
    integer(t);
  }
  /// Starts a row with no field yet (files without a time column).
  void begin_row(std::size_t sample) {
    sample_ = sample;
    column_ = 0;
  }
  void end_row() {
    if (column_ != columns_.size()) throw std::logic_error("navaid csv writer: wrong column count in " + file_);
    text_ += '\n';
  }
  void number(double value) {
    if (!std::isfinite(value)) fail("column '" + columns_[column_] + "' is not finite (" + shortest(value) + ")");
    field(shortest(value));
  }
  void number_or_empty(double value) {
    if (std::isnan(value)) return field("");
    number(value);
  }
  void integer(long long value) { field(std::to_string(value)); }
  void vec3(const Vec3& v) {
    for (int i = 0; i < 3; ++i) number(v[i]);
  }
  void optional_vec3(const std::optional<Vec3>& v) {
    if (!v) {
      for (int i = 0; i < 3; ++i) field("");
      return;
    }
    vec3(*v);
  }
  void field(const std::string& text) {
    if (column_ > 0) text_ += ',';
    text_ += text;
    ++column_;
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw IoError(file_, noun_ + " " + std::to_string(sample_) + ": " + message);
  }
  /// What one element of the written vector is called in messages ("sample", "frame", ...).
  void set_noun(std::string noun) { noun_ = std::move(noun); }
  void require_increasing(const std::optional<Timestamp>& previous, Timestamp t) const {
    if (previous && t <= *previous)
      fail("timestamp " + format_seconds(t) + " s is not after the previous sample's " + format_seconds(*previous) +
           " s (samples must be strictly increasing in time)");
  }
  const std::string& text() const { return text_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::vector<std::string> columns_;
  std::string text_;
  std::string noun_ = "sample";
  std::size_t sample_ = 0;
  std::size_t column_ = 0;
};

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(path.string(), "cannot open for writing");
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw IoError(path.string(), "write error");
}

class YamlWriter {
 public:
  explicit YamlWriter(std::string file) : file_(std::move(file)) {}
  void line(const std::string& text) { text_ += text + "\n"; }
  std::string number(double value, const std::string& key) const {
    if (!std::isfinite(value)) throw ConfigError(file_, key, "cannot write a non-finite value");
    return yaml_number(value);
  }
  std::string list(const std::vector<double>& values, const std::string& key) const {
    std::string s = "[";
    for (std::size_t i = 0; i < values.size(); ++i) s += (i ? ", " : "") + number(values[i], key);
    return s + "]";
  }
  void transform(const std::string& indent, const std::string& name, const SE3& T, const std::string& key) {
    line(indent + name + ":");
    line(indent + "  q_wxyz: " + list({T.q.w(), T.q.x(), T.q.y(), T.q.z()}, key + ".q_wxyz"));
    line(indent + "  t_m: " + list({T.t.x(), T.t.y(), T.t.z()}, key + ".t_m"));
  }
  const std::string& text() const { return text_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::string text_;
};

std::string calibration_text(const RigCalibration& rig, const fs::path& path) {
  YamlWriter y(path.string());
  y.line("# navaid recording calibration, format version " + std::to_string(kNavaidFormatVersion) +
         " (docs/recording-format.md)");
  if (rig.cameras.empty()) y.line("cameras: []");
  else y.line("cameras:");
  std::set<std::string> names;
  for (std::size_t i = 0; i < rig.cameras.size(); ++i) {
    const CameraCalibration& c = rig.cameras[i];
    const std::string key = "cameras[" + std::to_string(i) + "]";
    if (!valid_camera_name(c.name))
      throw ConfigError(y.file(), key + ".name", "'" + c.name + "' is not a valid camera name");
    if (!names.insert(c.name).second) throw ConfigError(y.file(), key + ".name", "duplicate camera name");
    if (c.width <= 0 || c.height <= 0) throw ConfigError(y.file(), key + ".resolution", "must be positive");
    if (!(c.fx > 0 && c.fy > 0)) throw ConfigError(y.file(), key + ".intrinsics", "fx, fy must be positive");
    y.line("  - name: " + c.name);
    y.line("    resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]");
    y.line("    intrinsics: " + y.list({c.fx, c.fy, c.cx, c.cy}, key + ".intrinsics"));
    const char* model = c.distortion == DistortionModel::kRadialTangential ? "radtan"
                        : c.distortion == DistortionModel::kEquidistant    ? "equidistant"
                                                                           : "none";
    y.line(std::string("    distortion_model: ") + model);
    y.line("    distortion_coeffs: " + y.list(c.distortion_coeffs, key + ".distortion_coeffs"));
    y.transform("    ", "T_B_C", c.T_B_C, key + ".T_B_C");
    y.line("    time_offset_s: " + y.number(c.time_offset_s, key + ".time_offset_s"));
    y.line("    rate_hz: " + y.number(c.rate_hz, key + ".rate_hz"));
    if (c.depth_min_m != 0 || c.depth_max_m != 0 || c.depth_baseline_m != 0 || c.depth_disparity_sigma_px != 0) {
      y.line("    depth:");
      y.line("      min_m: " + y.number(c.depth_min_m, key + ".depth.min_m"));
      y.line("      max_m: " + y.number(c.depth_max_m, key + ".depth.max_m"));
      y.line("      baseline_m: " + y.number(c.depth_baseline_m, key + ".depth.baseline_m"));
      y.line("      disparity_sigma_px: " + y.number(c.depth_disparity_sigma_px, key + ".depth.disparity_sigma_px"));
    }
  }
  if (rig.imu) {
    const ImuCalibration& c = *rig.imu;
    y.line("imu:");
    y.line("  rate_hz: " + y.number(c.rate_hz, "imu.rate_hz"));
    y.line("  gyroscope_noise_density: " + y.number(c.gyro_noise_density, "imu.gyroscope_noise_density"));
    y.line("  gyroscope_random_walk: " + y.number(c.gyro_random_walk, "imu.gyroscope_random_walk"));
    y.line("  accelerometer_noise_density: " + y.number(c.accel_noise_density, "imu.accelerometer_noise_density"));
    y.line("  accelerometer_random_walk: " + y.number(c.accel_random_walk, "imu.accelerometer_random_walk"));
    y.transform("  ", "T_B_I", c.T_B_I, "imu.T_B_I");
  }
  if (!rig.gps_lever_arm_B.isZero(0) || rig.gps_rate_hz) {
    y.line("gps:");
    const Vec3& a = rig.gps_lever_arm_B;
    y.line("  lever_arm_B_m: " + y.list({a.x(), a.y(), a.z()}, "gps.lever_arm_B_m"));
    if (rig.gps_rate_hz) y.line("  rate_hz: " + y.number(*rig.gps_rate_hz, "gps.rate_hz"));
  }
  if (rig.mag_rate_hz) {
    y.line("mag:");
    y.line("  rate_hz: " + y.number(*rig.mag_rate_hz, "mag.rate_hz"));
  }
  return y.text();
}

std::string recording_text(const Recording& rec, const fs::path& path, const std::vector<std::string>& sensors) {
  YamlWriter y(path.string());
  y.line("# navaid recording (docs/recording-format.md)");
  y.line(std::string("format: ") + kNavaidFormatName);
  y.line("version: " + std::to_string(kNavaidFormatVersion));
  std::string list;
  for (const auto& s : sensors) list += (list.empty() ? "" : ", ") + s;
  y.line("sensors: [" + list + "]");
  if (rec.origin) {
    y.line("origin:");
    y.line("  latitude_deg: " + y.number(rec.origin->latitude_deg, "origin.latitude_deg"));
    y.line("  longitude_deg: " + y.number(rec.origin->longitude_deg, "origin.longitude_deg"));
    y.line("  height_m: " + y.number(rec.origin->height_m, "origin.height_m"));
  }
  return y.text();
}

std::string imu_text(const std::vector<ImuSample>& samples, const fs::path& path) {
  CsvWriter w(path, kImuHeader);
  std::optional<Timestamp> previous;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const ImuSample& s = samples[i];
    w.begin_row(s.t, i);
    w.require_increasing(previous, s.t);
    previous = s.t;
    w.optional_vec3(s.has_gyro ? std::optional<Vec3>(s.gyro) : std::nullopt);
    w.vec3(s.accel);
    w.end_row();
  }
  return w.text();
}

std::string gps_text(const std::vector<GpsFix>& fixes, const fs::path& path) {
  CsvWriter w(path, kGpsHeader);
  std::optional<Timestamp> previous;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const GpsFix& f = fixes[i];
    w.begin_row(f.t, i);
    w.require_increasing(previous, f.t);
    previous = f.t;
    if (!(std::abs(f.latitude_deg) <= 90 && std::abs(f.longitude_deg) <= 180))
      w.fail("latitude/longitude " + shortest(f.latitude_deg) + ", " + shortest(f.longitude_deg) +
             " are not degrees within [-90, 90] x [-180, 180]");
    const int mode = static_cast<int>(f.mode);
    if (mode < 1 || mode > 3) w.fail("fix mode " + std::to_string(mode) + " is not 1, 2 or 3");
    if (f.quality < 0 || f.quality > 9) w.fail("quality " + std::to_string(f.quality) + " is outside [0, 9]");
    if (f.satellites < 0 && f.satellites != kUnknownSatellites)
      w.fail("satellite count " + std::to_string(f.satellites) + " (use -1 for unknown)");
    if (f.hdop < 0) w.fail("negative hdop");
    const Mat3& c = f.covariance_enu;
    if (!(c(0, 0) >= 0 && c(1, 1) >= 0 && c(2, 2) >= 0)) w.fail("ENU covariance has a negative variance");
    w.number(f.latitude_deg);
    w.number(f.longitude_deg);
    w.number_or_empty(f.altitude_m);
    w.number_or_empty(f.geoid_separation_m);
    w.integer(mode);
    w.integer(f.quality);
    if (f.satellites == kUnknownSatellites) w.field("");
    else w.integer(f.satellites);
    w.number_or_empty(f.hdop);
    for (const double v : {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)}) w.number(v);
    w.end_row();
  }
  return w.text();
}

std::string mag_text(const std::vector<MagSample>& samples, const fs::path& path) {
  CsvWriter w(path, kMagHeader);
  std::optional<Timestamp> previous;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    w.begin_row(samples[i].t, i);
    w.require_increasing(previous, samples[i].t);
    previous = samples[i].t;
    w.vec3(samples[i].field);
    w.end_row();
  }
  return w.text();
}

std::string groundtruth_text(const std::vector<GroundTruthState>& states, const fs::path& path) {
  CsvWriter w(path, kGroundtruthHeader);
  std::optional<Timestamp> previous;
  for (std::size_t i = 0; i < states.size(); ++i) {
    const GroundTruthState& g = states[i];
    w.begin_row(g.t, i);
    w.require_increasing(previous, g.t);
    previous = g.t;
    w.vec3(g.T_W_B.t);
    const Quat& q = g.T_W_B.q;
    if (std::abs(q.norm() - 1.0) > kUnitQuaternionRejectTolerance) w.fail("quaternion is not unit");
    for (const double v : {q.w(), q.x(), q.y(), q.z()}) w.number(v);
    w.optional_vec3(g.v_W);
    w.optional_vec3(g.b_g);
    w.optional_vec3(g.b_a);
    w.end_row();
  }
  return w.text();
}

// Planned output of one frame: where each image comes from and goes to.
struct FramePlan {
  const RgbdFrame* frame;
  std::string intensity, depth, labels, confidence;  // relative output paths, empty when absent
};

std::string frames_text(const std::vector<RgbdFrame>& frames, const fs::path& path, const NavaidWriteOptions& options,
                        std::vector<FramePlan>& plans) {
  CsvWriter w(path, kFramesHeader);
  std::map<std::string, Timestamp> last_of_camera;
  std::optional<Timestamp> previous_row;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const RgbdFrame& f = frames[i];
    w.begin_row(f.t, i);
    if (!valid_camera_name(f.camera))
      w.fail("camera '" + f.camera + "' is not a valid camera name (letter, then letters, digits, _ or -)");
    if (previous_row && f.t < *previous_row) w.fail("frames must be in time order");
    previous_row = f.t;
    const auto last = last_of_camera.find(f.camera);
    w.require_increasing(last == last_of_camera.end() ? std::nullopt : std::optional<Timestamp>(last->second), f.t);
    last_of_camera[f.camera] = f.t;
    if (f.class_probabilities && !options.drop_class_probabilities)
      w.fail("carries per-class probabilities, which the navaid recording format does not store "
             "(store label_confidence instead, or set drop_class_probabilities to write without them)");
    if (f.index > static_cast<std::uint64_t>(std::numeric_limits<long long>::max())) w.fail("frame index too large");

    FramePlan plan{&f, {}, {}, {}, {}};
    const std::string stem = f.camera + "_" + std::to_string(f.t) + ".png";
    if (!f.intensity_path.empty() || !f.intensity.empty()) plan.intensity = std::string(kRgbDir) + "/" + stem;
    if (!f.depth_path.empty() || !f.depth.empty()) plan.depth = std::string(kDepthDir) + "/" + stem;
    if (!f.labels_path.empty() || f.labels) plan.labels = std::string(kLabelsDir) + "/" + stem;
    if (!f.confidence_path.empty() || f.label_confidence) {
      if (plan.labels.empty()) w.fail("has a label confidence but no labels");
      plan.confidence = std::string(kConfidenceDir) + "/" + stem;
    }
    w.field(f.camera);
    w.integer(static_cast<long long>(f.index));
    w.field(plan.intensity);
    w.field(plan.depth);
    w.field(plan.labels);
    w.field(plan.confidence);
    w.end_row();
    plans.push_back(plan);
  }
  return w.text();
}

// images_in_place: each image must already be where the plan puts it.
void check_frame_images_in_place(const FramePlan& plan, const fs::path& folder) {
  const RgbdFrame& f = *plan.frame;
  const std::pair<const std::string*, const std::string*> pairs[] = {
      {&plan.intensity, &f.intensity_path}, {&plan.depth, &f.depth_path}, {&plan.labels, &f.labels_path},
      {&plan.confidence, &f.confidence_path}};
  for (const auto& [planned, source] : pairs) {
    if (planned->empty()) continue;
    const fs::path target = folder / *planned;
    std::error_code ec;
    if (source->empty() || !fs::equivalent(*source, target, ec))
      throw IoError(target.string(), "images_in_place: frame " + std::to_string(f.index) + " has its image at '" +
                                         *source + "', not at the recording's own path");
  }
}

void write_frame_images(const FramePlan& plan, const fs::path& folder, int compression) {
  const RgbdFrame& f = *plan.frame;
  if (!plan.intensity.empty()) {
    const std::string out = (folder / plan.intensity).string();
    write_png(out, f.intensity_path.empty() ? f.intensity : read_intensity_image(f.intensity_path), compression);
  }
  if (!plan.depth.empty()) {
    const std::string out = (folder / plan.depth).string();
    if (!f.depth_path.empty()) {
      const ImageU16 raw = read_depth_png_raw(f.depth_path, f.depth_png_scale_m);
      write_png(out, convert_depth_units(raw, f.depth_png_scale_m, kNavaidDepthScaleM, f.depth_path), compression);
    } else {
      write_png(out, depth_to_png_units(f.depth, kNavaidDepthScaleM, out), compression);
    }
  }
  if (plan.labels.empty()) return;
  const std::string labels_out = (folder / plan.labels).string();
  const ImageU8 labels = f.labels_path.empty() ? *f.labels : read_label_image(f.labels_path);
  if (labels.channels != 1) throw IoError(labels_out, "labels must have one channel (class id per pixel)");
  write_png(labels_out, labels, compression);
  if (plan.confidence.empty()) return;
  const std::string out = (folder / plan.confidence).string();
  const ImageU8 confidence = f.confidence_path.empty() ? confidence_to_png_units(*f.label_confidence, out)
                                                       : read_confidence_png_raw(f.confidence_path);
  if (confidence.width != labels.width || confidence.height != labels.height)
    throw IoError(out, "label confidence is " + std::to_string(confidence.width) + "x" +
                           std::to_string(confidence.height) + " but the labels are " + std::to_string(labels.width) +
                           "x" + std::to_string(labels.height));
  write_png(out, confidence, compression);
}

std::string features_text(const std::vector<FeatureFrame>& frames, const fs::path& path) {
  CsvWriter w(path, kFeaturesHeader);
  w.set_noun("feature frame");
  std::map<std::string, Timestamp> last_of_camera;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const FeatureFrame& f = frames[i];
    w.begin_row(i);  // for the checks' messages; the rows follow
    if (!valid_camera_name(f.camera))
      w.fail("camera '" + f.camera + "' is not a valid camera name (letter, then letters, digits, _ or -)");
    if (i > 0 && f.t < frames[i - 1].t) w.fail("feature frames must be in time order");
    const auto last = last_of_camera.find(f.camera);
    w.require_increasing(last == last_of_camera.end() ? std::nullopt : std::optional<Timestamp>(last->second), f.t);
    last_of_camera[f.camera] = f.t;
    if (f.features.empty()) {  // the "frame without features" marker row
      w.begin_row(f.t, i);
      w.field(f.camera);
      for (int k = 0; k < 4; ++k) w.field("");
      w.end_row();
    }
    for (std::size_t k = 0; k < f.features.size(); ++k) {
      const FeatureObservation& o = f.features[k];
      if (k > 0 && o.track_id <= f.features[k - 1].track_id)
        w.fail("track id " + std::to_string(o.track_id) + " after " + std::to_string(f.features[k - 1].track_id) +
               " (track ids must be strictly increasing within a frame)");
      if (o.track_id > static_cast<std::uint64_t>(kMaxTrackId)) w.fail("track id too large");
      if (o.depth_m && !(std::isfinite(*o.depth_m) && *o.depth_m > 0))
        w.fail("track " + std::to_string(o.track_id) + ": depth " + shortest(*o.depth_m) +
               " is not a positive finite number (use no depth instead)");
      w.begin_row(f.t, i);
      w.field(f.camera);
      w.integer(static_cast<long long>(o.track_id));
      w.number(o.uv.x());
      w.number(o.uv.y());
      if (o.depth_m) w.number(*o.depth_m);
      else w.field("");
      w.end_row();
    }
  }
  return w.text();
}

std::string landmarks_text(const std::vector<Landmark>& landmarks, const fs::path& path) {
  CsvWriter w(path, kLandmarksHeader);
  w.set_noun("landmark");
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const Landmark& l = landmarks[i];
    w.begin_row(i);
    if (i > 0 && l.id <= landmarks[i - 1].id)
      w.fail("track id " + std::to_string(l.id) + " after " + std::to_string(landmarks[i - 1].id) +
             " (landmarks must be sorted by strictly increasing track id)");
    if (l.id > static_cast<std::uint64_t>(kMaxTrackId)) w.fail("track id too large");
    w.integer(static_cast<long long>(l.id));
    w.vec3(l.p_W);
    w.end_row();
  }
  return w.text();
}

bool is_inside(const fs::path& file, const fs::path& folder) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(folder, ec);
  const fs::path b = fs::weakly_canonical(file, ec);
  auto ia = a.begin();
  auto ib = b.begin();
  for (; ia != a.end(); ++ia, ++ib) {
    if (ia->empty()) continue;  // trailing separator
    if (ib == b.end() || *ia != *ib) return false;
  }
  return true;
}

// The recording's own entries, removed before an overwrite.
const char* const kOwnEntries[] = {kRecordingYaml, kCalibrationYaml, kImuCsv,       kGpsCsv,
                                   kMagCsv,        kGroundtruthCsv,  kFramesCsv,    kFeaturesCsv,
                                   kLandmarksCsv,  kRgbDir,          kDepthDir,     kLabelsDir,
                                   kConfidenceDir};

void prepare_folder(const Recording& rec, const fs::path& folder, const NavaidWriteOptions& options) {
  std::error_code ec;
  if (fs::exists(folder, ec)) {
    if (!fs::is_directory(folder, ec)) throw IoError(folder.string(), "exists and is not a folder");
    if (!fs::is_empty(folder, ec)) {
      if (!options.overwrite)
        throw IoError(folder.string(), "folder is not empty (set overwrite to replace a recording there)");
      if (!options.images_in_place)
        for (const auto& f : rec.frames)
          for (const std::string* p : {&f.intensity_path, &f.depth_path, &f.labels_path, &f.confidence_path})
            if (!p->empty() && is_inside(*p, folder))
              throw IoError(folder.string(), "cannot overwrite the folder that frame images are read from (" + *p + ")");
      for (const char* entry : kOwnEntries) {
        const std::string_view e(entry);
        const bool image_dir = e == kRgbDir || e == kDepthDir || e == kLabelsDir || e == kConfidenceDir;
        if (!(options.images_in_place && image_dir)) fs::remove_all(folder / entry, ec);
      }
      if (ec) throw IoError(folder.string(), "cannot remove the previous recording: " + ec.message());
    }
  }
  fs::create_directories(folder, ec);
  if (ec) throw IoError(folder.string(), "cannot create folder: " + ec.message());
}

}  // namespace

// ------------------------------------------------------------------------------------------------

bool is_navaid_recording(const fs::path& folder) {
  std::error_code ec;
  return fs::is_regular_file(folder / kRecordingYaml, ec);
}

Recording read_navaid_recording(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw IoError(folder.string(), "not a folder (expected a navaid recording)");
  Recording rec;
  rec.path = folder.string();
  rec.format = "navaid";
  std::set<std::string> sensors;
  const int version = read_recording_yaml(folder / kRecordingYaml, rec, sensors);
  rec.calibration = read_calibration_yaml(folder / kCalibrationYaml);

  for (const auto& stream : kStreams) {
    const fs::path file = folder / stream.file;
    if (!sensors.count(stream.sensor)) {
      if (fs::exists(file, ec))
        rec.report.warn(file.string(), std::string("ignored: sensor '") + stream.sensor +
                                           "' is not listed in recording.yaml");
      continue;
    }
    if (!fs::exists(file, ec))
      throw IoError(file.string(), std::string("missing, but recording.yaml lists sensor '") + stream.sensor + "'");
    const std::string name = stream.sensor;
    if (name == "imu") read_imu(file, rec);
    else if (name == "frames") read_frames(file, folder, version, rec);
    else if (name == "gps") read_gps(file, rec);
    else if (name == "mag") read_mag(file, rec);
    else if (name == "groundtruth") read_groundtruth(file, rec);
    else if (name == "features") read_features(file, rec);
    else read_landmarks(file, rec);
  }
  return rec;
}

void write_navaid_recording(const Recording& rec, const fs::path& folder, const NavaidWriteOptions& options) {
  // Everything is formatted (and validated) in memory before the disk is touched.
  std::vector<std::string> sensors;
  std::vector<std::pair<const char*, std::string>> csv_files;
  std::vector<FramePlan> plans;
  if (!rec.imu.empty()) {
    sensors.emplace_back("imu");
    csv_files.emplace_back(kImuCsv, imu_text(rec.imu, folder / kImuCsv));
  }
  if (!rec.frames.empty()) {
    sensors.emplace_back("frames");
    csv_files.emplace_back(kFramesCsv, frames_text(rec.frames, folder / kFramesCsv, options, plans));
  }
  if (!rec.gps.empty()) {
    sensors.emplace_back("gps");
    csv_files.emplace_back(kGpsCsv, gps_text(rec.gps, folder / kGpsCsv));
  }
  if (!rec.mag.empty()) {
    sensors.emplace_back("mag");
    csv_files.emplace_back(kMagCsv, mag_text(rec.mag, folder / kMagCsv));
  }
  if (!rec.groundtruth.empty()) {
    sensors.emplace_back("groundtruth");
    csv_files.emplace_back(kGroundtruthCsv, groundtruth_text(rec.groundtruth, folder / kGroundtruthCsv));
  }
  if (!rec.features.empty()) {
    sensors.emplace_back("features");
    csv_files.emplace_back(kFeaturesCsv, features_text(rec.features, folder / kFeaturesCsv));
  }
  if (!rec.landmarks.empty()) {
    sensors.emplace_back("landmarks");
    csv_files.emplace_back(kLandmarksCsv, landmarks_text(rec.landmarks, folder / kLandmarksCsv));
  }
  const std::string calibration = calibration_text(rec.calibration, folder / kCalibrationYaml);
  const std::string recording = recording_text(rec, folder / kRecordingYaml, sensors);

  prepare_folder(rec, folder, options);
  std::error_code ec;
  const auto make_dir = [&](const char* name, bool needed) {
    if (!needed) return;
    fs::create_directories(folder / name, ec);
    if (ec) throw IoError((folder / name).string(), "cannot create folder: " + ec.message());
  };
  bool any_intensity = false, any_depth = false, any_labels = false, any_confidence = false;
  for (const auto& p : plans) {
    any_intensity = any_intensity || !p.intensity.empty();
    any_depth = any_depth || !p.depth.empty();
    any_labels = any_labels || !p.labels.empty();
    any_confidence = any_confidence || !p.confidence.empty();
  }
  make_dir(kRgbDir, any_intensity);
  make_dir(kDepthDir, any_depth);
  make_dir(kLabelsDir, any_labels);
  make_dir(kConfidenceDir, any_confidence);
  for (std::size_t i = 0; i < plans.size(); ++i) {
    if (options.images_in_place) check_frame_images_in_place(plans[i], folder);
    else write_frame_images(plans[i], folder, options.png_compression);
    if (options.on_frame_written) options.on_frame_written(i + 1, plans.size());
  }

  for (const auto& [name, text] : csv_files) write_file(folder / name, text);
  write_file(folder / kCalibrationYaml, calibration);
  // Last: a folder without recording.yaml is an interrupted write, not a recording.
  write_file(folder / kRecordingYaml, recording);
}

}  // namespace navaid::io
