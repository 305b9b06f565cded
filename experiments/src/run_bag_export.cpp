// A run folder as a ROS 1 bag for RViz (run_bag_export.hpp).
#include "navaid/experiments/run_bag_export.hpp"

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "navaid/core/csv_field.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/semantic_classes.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/io/open_input.hpp"
#include "navaid/io/text_file.hpp"
#include "navaid/mapping/collision_map.hpp"

namespace navaid::experiments {
namespace {

namespace fs = std::filesystem;

constexpr const char* kWorld = "world";
constexpr const char* kBody = "body";
constexpr const char* kCamera = "camera";

ros::Time ros_time(Timestamp t, const std::string& what) {
  if (t < 0) throw IoError(what, "a time before 1970 cannot be a ROS time");
  ros::Time r;
  r.fromNSec(static_cast<std::uint64_t>(t));
  return r;
}

geometry_msgs::Pose pose_msg(const SE3& T) {
  geometry_msgs::Pose p;
  p.position.x = T.t.x();
  p.position.y = T.t.y();
  p.position.z = T.t.z();
  p.orientation.w = T.q.w();
  p.orientation.x = T.q.x();
  p.orientation.y = T.q.y();
  p.orientation.z = T.q.z();
  return p;
}

geometry_msgs::TransformStamped transform_msg(const SE3& T, const ros::Time& t, const char* parent, const char* child) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = t;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = T.t.x();
  m.transform.translation.y = T.t.y();
  m.transform.translation.z = T.t.z();
  m.transform.rotation.w = T.q.w();
  m.transform.rotation.x = T.q.x();
  m.transform.rotation.y = T.q.y();
  m.transform.rotation.z = T.q.z();
  return m;
}

// ROS's pose covariance: [x y z rx ry rz], rotation about the header frame's fixed axes. Ours is on
// the right (body axes): Sigma_W = R Sigma_B R^T. estimates.csv keeps no cross terms.
boost::array<double, 36> pose_covariance(const StateEstimate& e) {
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  const Mat3 R = e.T_W_B.q.toRotationMatrix();
  c.block<3, 3>(0, 0) = e.covariance.block<3, 3>(3, 3);
  c.block<3, 3>(3, 3) = R * e.covariance.block<3, 3>(0, 0) * R.transpose();
  boost::array<double, 36> out{};
  for (int r = 0; r < 6; ++r)
    for (int k = 0; k < 6; ++k) out[static_cast<std::size_t>(6 * r + k)] = c(r, k);
  return out;
}

// The newest estimate at or before t (the first one before the run's start).
const StateEstimate& estimate_at(const std::vector<StateEstimate>& estimates, Timestamp t) {
  auto it = std::upper_bound(estimates.begin(), estimates.end(), t,
                             [](Timestamp v, const StateEstimate& e) { return v < e.t; });
  return it == estimates.begin() ? estimates.front() : *std::prev(it);
}

double x_axis_heading(const SE3& T) {
  const Vec3 x = T.q * Vec3::UnitX();
  return std::atan2(x.y(), x.x());
}

// The fields of a CSV line that navaid wrote (quoted free text allowed); IoError at an open quote.
std::vector<std::string> csv_fields(const io::TextFile& file, const std::string& line) {
  auto fields = split_csv_fields(line);
  if (!fields) file.fail("a quoted field is not closed");
  return *fields;
}

// Column index by name in a CSV header; IoError naming the file when absent.
std::size_t column(const io::TextFile& file, const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) file.fail("no column '" + name + "'");
  return static_cast<std::size_t>(it - header.begin());
}

struct MapPoint {
  float x, y, z;
  std::uint8_t r, g, b, class_id;
  float probability, occupancy;
};

// map.ply as the map session writes it (docs/mapping.md): ASCII, one vertex element with the
// properties in this order.
std::vector<MapPoint> read_map_ply(const fs::path& path) {
  io::TextFile file(path);
  std::string line;
  const std::vector<std::string> expected{"x", "y", "z", "red", "green", "blue", "class_id", "class_probability",
                                          "occupancy"};
  std::vector<std::string> properties;
  std::size_t count = 0;
  bool ended = false;
  if (!file.next(line) || io::trim(line) != "ply") file.fail("not a PLY file");
  while (!ended && file.next(line)) {
    std::istringstream words{std::string(io::trim(line))};
    std::string word;
    words >> word;
    if (word == "format" || word == "comment") {
      std::string format;
      words >> format;
      if (word == "format" && format != "ascii") file.fail("only ASCII PLY is read (found '" + format + "')");
    } else if (word == "element") {
      std::string name;
      words >> name >> count;
      if (name != "vertex") file.fail("unexpected element '" + name + "'");
    } else if (word == "property") {
      std::string type, name;
      words >> type >> name;
      properties.push_back(name);
    } else if (word == "end_header") {
      ended = true;
    } else {
      file.fail("unexpected header line '" + io::printable(line) + "'");
    }
  }
  if (!ended) file.fail("no end_header");
  if (properties != expected) file.fail("vertex properties are not x y z red green blue class_id class_probability occupancy");
  std::vector<MapPoint> points;
  points.reserve(count);
  while (points.size() < count && file.next(line)) {
    const auto f = io::split_fields(io::trim(line), ' ');
    io::require_field_count(file, f, expected.size());
    const auto byte = [&](std::string_view text, std::string_view name) {
      const long long v = io::parse_integer(file, text, name);
      if (v < 0 || v > 255) file.fail(std::string(name) + " outside 0..255");
      return static_cast<std::uint8_t>(v);
    };
    MapPoint p{};
    p.x = static_cast<float>(io::parse_double(file, f[0], "x"));
    p.y = static_cast<float>(io::parse_double(file, f[1], "y"));
    p.z = static_cast<float>(io::parse_double(file, f[2], "z"));
    p.r = byte(f[3], "red");
    p.g = byte(f[4], "green");
    p.b = byte(f[5], "blue");
    p.class_id = byte(f[6], "class_id");
    p.probability = static_cast<float>(io::parse_double(file, f[7], "class_probability"));
    p.occupancy = static_cast<float>(io::parse_double(file, f[8], "occupancy"));
    points.push_back(p);
  }
  if (points.size() != count)
    file.fail("holds " + std::to_string(points.size()) + " vertices, the header says " + std::to_string(count));
  return points;
}

sensor_msgs::PointCloud2 point_cloud(const std::vector<MapPoint>& points, const ros::Time& t) {
  sensor_msgs::PointCloud2 c;
  c.header.stamp = t;
  c.header.frame_id = kWorld;
  c.height = 1;
  c.width = static_cast<std::uint32_t>(points.size());
  const auto field = [&c](const char* name, std::uint32_t offset, std::uint8_t type) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    c.fields.push_back(f);
  };
  // RViz reads colour from a float32 "rgb" field whose bytes are 0x00RRGGBB.
  field("x", 0, sensor_msgs::PointField::FLOAT32);
  field("y", 4, sensor_msgs::PointField::FLOAT32);
  field("z", 8, sensor_msgs::PointField::FLOAT32);
  field("rgb", 12, sensor_msgs::PointField::FLOAT32);
  field("class_id", 16, sensor_msgs::PointField::UINT8);
  field("probability", 20, sensor_msgs::PointField::FLOAT32);
  field("occupancy", 24, sensor_msgs::PointField::FLOAT32);
  c.point_step = 28;
  c.row_step = c.point_step * c.width;
  c.is_bigendian = false;
  c.is_dense = true;
  c.data.resize(static_cast<std::size_t>(c.row_step));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const MapPoint& p = points[i];
    std::uint8_t* d = c.data.data() + i * c.point_step;
    const std::uint32_t rgb = (std::uint32_t{p.r} << 16) | (std::uint32_t{p.g} << 8) | p.b;
    std::memcpy(d + 0, &p.x, 4);
    std::memcpy(d + 4, &p.y, 4);
    std::memcpy(d + 8, &p.z, 4);
    std::memcpy(d + 12, &rgb, 4);
    d[16] = p.class_id;
    std::memcpy(d + 20, &p.probability, 4);
    std::memcpy(d + 24, &p.occupancy, 4);
  }
  return c;
}

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0F) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker marker(const ros::Time& t, const char* ns, std::int32_t type) {
  visualization_msgs::Marker m;
  m.header.stamp = t;
  m.header.frame_id = kWorld;
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

// Occupied voxels whose class blocks the way (the collision map's default table, p >= 0.5).
visualization_msgs::Marker obstacle_marker(const std::vector<MapPoint>& points, double voxel_m, const ros::Time& t) {
  auto m = marker(t, "obstacles", visualization_msgs::Marker::CUBE_LIST);
  m.scale.x = m.scale.y = m.scale.z = voxel_m;
  const auto& table = mapping::default_semantic_collision_table();
  for (const MapPoint& p : points) {
    if (p.class_id >= table.size() || table[p.class_id] < 0.5) continue;
    geometry_msgs::Point q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    m.points.push_back(q);
    m.colors.push_back(rgba(p.r / 255.0F, p.g / 255.0F, p.b / 255.0F, 0.9F));
  }
  return m;
}

double map_resolution(const fs::path& map_dir) {
  std::ifstream in(map_dir / "summary.json");
  if (!in) return 0.1;
  try {
    const auto j = nlohmann::json::parse(in);
    return j.at("map").at("resolution_m").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw IoError((map_dir / "summary.json").string(), std::string("no map.resolution_m: ") + e.what());
  }
}

class BagOut {
 public:
  BagOut(const fs::path& path, const std::string& compression) {
    try {
      bag_.open(path.string(), rosbag::bagmode::Write);
      bag_.setCompression(compression == "bz2"   ? rosbag::compression::BZ2
                          : compression == "lz4" ? rosbag::compression::LZ4
                                                 : rosbag::compression::Uncompressed);
    } catch (const std::exception& e) {
      throw IoError(path.string(), std::string("cannot write the bag: ") + e.what());
    }
  }
  template <class Msg>
  void write(const std::string& topic, const ros::Time& t, const Msg& msg) {
    try {
      bag_.write(topic, t, msg);
    } catch (const std::exception& e) {
      throw IoError(bag_.getFileName(), "cannot write " + topic + ": " + e.what());
    }
    ++counts[topic];
  }
  void close() { bag_.close(); }
  RunBagExportCounts counts;

 private:
  rosbag::Bag bag_;
};

nav_msgs::Path path_msg(const std::vector<StateEstimate>& estimates, std::size_t end, std::size_t max_poses) {
  nav_msgs::Path p;
  p.header.stamp = ros_time(estimates[end - 1].t, "estimates.csv");
  p.header.frame_id = kWorld;
  const std::size_t step = std::max<std::size_t>(1, (end + max_poses - 1) / max_poses);
  for (std::size_t i = (end - 1) % step; i < end; i += step) {  // evenly thinned, always the newest
    geometry_msgs::PoseStamped s;
    s.header.stamp = ros_time(estimates[i].t, "estimates.csv");
    s.header.frame_id = kWorld;
    s.pose = pose_msg(estimates[i].T_W_B);
    p.poses.push_back(s);
  }
  return p;
}

void write_plans(BagOut& bag, const fs::path& file, const std::vector<StateEstimate>& estimates) {
  io::TextFile in(file);
  std::string line;
  if (!in.next(line)) return;
  const auto header = csv_fields(in, line);
  const std::size_t c_t = column(in, header, "t_ns"), c_status = column(in, header, "status"),
                    c_path = column(in, header, "path");
  while (in.next(line)) {
    if (io::is_blank_or_comment(line)) continue;
    const auto f = csv_fields(in, line);
    if (f.size() != header.size()) in.fail("expected " + std::to_string(header.size()) + " fields");
    const Timestamp t = io::parse_nanoseconds_field(in, f[c_t], "t_ns");
    const ros::Time stamp = ros_time(t, file.string());
    auto m = marker(stamp, "plan", visualization_msgs::Marker::LINE_STRIP);
    if (f[c_status] != "found" || f[c_path].empty()) {
      m.action = visualization_msgs::Marker::DELETE;  // no plan this time: the last one goes
    } else {
      const double z = estimate_at(estimates, t).T_W_B.t.z();
      std::istringstream points(f[c_path]);
      std::string xy;
      while (points >> xy) {
        const auto colon = xy.find(':');
        if (colon == std::string::npos) in.fail("path point '" + xy + "' is not x:y");
        geometry_msgs::Point q;
        q.x = io::parse_double(in, std::string_view(xy).substr(0, colon), "path x");
        q.y = io::parse_double(in, std::string_view(xy).substr(colon + 1), "path y");
        q.z = z;
        m.points.push_back(q);
      }
      m.scale.x = 0.04;
      m.color = rgba(0.1F, 0.8F, 0.2F);
    }
    visualization_msgs::MarkerArray a;
    a.markers.push_back(m);
    bag.write("/navaid/markers", stamp, a);
  }
}

// Each cue with a direction becomes an arrow from the user's estimated position, turned from the
// body's heading by direction_deg (positive to the left), with the cue's kind and text beside it.
void write_cues(BagOut& bag, const fs::path& file, const std::vector<StateEstimate>& estimates) {
  io::TextFile in(file);
  std::string line;
  if (!in.next(line)) return;
  const auto header = csv_fields(in, line);
  const std::size_t c_t = column(in, header, "t_s"), c_kind = column(in, header, "kind"),
                    c_dir = column(in, header, "direction_deg"), c_text = column(in, header, "text");
  while (in.next(line)) {
    if (io::is_blank_or_comment(line)) continue;
    const auto f = csv_fields(in, line);
    if (f.size() != header.size()) in.fail("expected " + std::to_string(header.size()) + " fields");
    if (f[c_dir].empty()) continue;
    const Timestamp t = io::parse_seconds_field(in, f[c_t], "t_s");
    const double direction = io::parse_double(in, f[c_dir], "direction_deg") * M_PI / 180.0;
    const ros::Time stamp = ros_time(t, file.string());
    const SE3& T = estimate_at(estimates, t).T_W_B;
    const double heading = x_axis_heading(T) + direction;
    auto arrow = marker(stamp, "cue", visualization_msgs::Marker::ARROW);
    geometry_msgs::Point from, to;
    from.x = T.t.x();
    from.y = T.t.y();
    from.z = T.t.z();
    to = from;
    to.x += 0.8 * std::cos(heading);
    to.y += 0.8 * std::sin(heading);
    arrow.points = {from, to};
    arrow.scale.x = 0.05;
    arrow.scale.y = 0.1;
    arrow.color = rgba(1.0F, 0.55F, 0.0F);
    arrow.lifetime = ros::Duration(1.0);
    auto text = marker(stamp, "cue_text", visualization_msgs::Marker::TEXT_VIEW_FACING);
    text.pose.position = to;
    text.pose.position.z += 0.2;
    text.scale.z = 0.15;
    text.color = rgba(1.0F, 1.0F, 1.0F);
    text.text = f[c_kind] + (f[c_text].empty() ? "" : ": " + f[c_text]);
    text.lifetime = ros::Duration(1.0);
    visualization_msgs::MarkerArray a;
    a.markers = {arrow, text};
    bag.write("/navaid/markers", stamp, a);
  }
}

fs::path recording_of(const RunBagExportOptions& o) {
  if (!o.recording.empty()) return o.recording;
  const fs::path named = run_recording(o.run);
  std::error_code ec;
  if (fs::exists(named, ec)) return named;
  // A relative path is relative to where navaid run was started: try beside the run folder too.
  if (named.is_relative() && fs::exists(o.run.parent_path() / named, ec)) return o.run.parent_path() / named;
  throw IoError((o.run / "summary.json").string(), "names the recording '" + named.string() +
                                                       "', which is not there; give it with --recording");
}

}  // namespace

RunBagExportCounts export_run_bag(const RunBagExportOptions& o) {
  if (o.compression != "none" && o.compression != "bz2" && o.compression != "lz4")
    throw UsageError("--compression must be none, bz2 or lz4, not '" + o.compression + "'");
  if (!(o.path_rate_hz > 0)) throw UsageError("the path rate must be positive");
  if (o.path_max_poses < 2) throw UsageError("a path message needs at least 2 poses");
  const std::vector<StateEstimate> estimates = read_estimates_csv(o.run / "estimates.csv");
  if (estimates.empty()) throw IoError((o.run / "estimates.csv").string(), "holds no estimate");
  const io::Recording recording = io::read_input(recording_of(o));
  if (recording.calibration.cameras.empty())
    throw IoError(recording.path, "has no camera in its calibration: no body -> camera transform to write");

  const fs::path map_dir = o.run / "map";
  std::vector<MapPoint> map;
  if (fs::exists(map_dir / "map.ply")) map = read_map_ply(map_dir / "map.ply");

  BagOut bag(o.bag, o.compression);
  const ros::Time first = ros_time(estimates.front().t, "estimates.csv");
  const ros::Time last = ros_time(estimates.back().t, "estimates.csv");
  tf2_msgs::TFMessage statics;
  statics.transforms.push_back(transform_msg(recording.calibration.cameras.front().T_B_C, first, kBody, kCamera));
  bag.write("/tf_static", first, statics);

  const Timestamp path_period = seconds_to_ns(1.0 / o.path_rate_hz);
  Timestamp next_path = estimates.front().t;
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    const StateEstimate& e = estimates[i];
    const ros::Time t = ros_time(e.t, "estimates.csv");
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(transform_msg(e.T_W_B, t, kWorld, kBody));
    bag.write("/tf", t, tf);
    geometry_msgs::PoseWithCovarianceStamped pose;
    pose.header.stamp = t;
    pose.header.frame_id = kWorld;
    pose.pose.pose = pose_msg(e.T_W_B);
    pose.pose.covariance = pose_covariance(e);
    bag.write("/navaid/pose", t, pose);
    if (e.t >= next_path || i + 1 == estimates.size()) {
      bag.write("/navaid/path", t, path_msg(estimates, i + 1, o.path_max_poses));
      next_path = e.t + path_period;
    }
  }
  if (!map.empty()) {
    bag.write("/navaid/map", last, point_cloud(map, last));
    visualization_msgs::MarkerArray a;
    a.markers.push_back(obstacle_marker(map, map_resolution(map_dir), last));
    bag.write("/navaid/markers", last, a);
  }
  if (fs::exists(o.run / "plans.csv")) write_plans(bag, o.run / "plans.csv", estimates);
  if (fs::exists(o.run / "cues.csv")) write_cues(bag, o.run / "cues.csv", estimates);
  bag.close();
  return bag.counts;
}

}  // namespace navaid::experiments
