// ROS 1 bag reader: topic choice by role, then one pass per chosen topic (rosbag_storage's View
// decodes bz2 / lz4 chunks). Every message's time is its header stamp.
#include "navaid/io/ros_bag.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/MagneticField.h>
#include <sensor_msgs/NavSatFix.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "navaid/core/errors.hpp"
#include "navaid/io/image_io.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "ros_bag_images.hpp"
#include "ros_bag_structure.hpp"

namespace navaid::io {
namespace {

namespace fs = std::filesystem;

constexpr const char* kImuType = "sensor_msgs/Imu";
constexpr const char* kImageType = "sensor_msgs/Image";
constexpr const char* kCompressedType = "sensor_msgs/CompressedImage";
constexpr const char* kCameraInfoType = "sensor_msgs/CameraInfo";
constexpr const char* kNavSatFixType = "sensor_msgs/NavSatFix";
constexpr const char* kMagType = "sensor_msgs/MagneticField";
constexpr const char* kPoseType = "geometry_msgs/PoseStamped";
constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kTfType = "tf2_msgs/TFMessage";
constexpr const char* kCamera = "cam0";
constexpr const char* kNone = "none";  // a role's topic that switches the role off

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// An open bag with its topics; every rosbag / serialization exception becomes an IoError naming
// the bag, the topic and the message.
class BagFile {
 public:
  explicit BagFile(const fs::path& path) : path_(path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw IoError(path.string(), "does not exist or is not a file");
    if (!is_ros_bag(path)) throw IoError(path.string(), "is not a ROS 1 bag (no '#ROSBAG V2.0' header)");
    detail::check_ros_bag_structure(path);  // rosbag_storage trusts the bag's lengths
    try {
      bag_.open(path.string(), rosbag::bagmode::Read);
      rosbag::View all(bag_);
      for (const rosbag::ConnectionInfo* c : all.getConnections()) {
        auto& t = topics_[c->topic];
        if (!t.type.empty() && t.type != c->datatype)
          throw IoError(path.string(), "topic " + c->topic + " carries two types (" + t.type + ", " + c->datatype + ")");
        t.type = c->datatype;
      }
      for (auto& [name, t] : topics_) t.messages = rosbag::View(bag_, rosbag::TopicQuery(name)).size();
    } catch (const IoError&) {
      throw;
    } catch (const std::exception& e) {
      throw IoError(path.string(), std::string("cannot read the bag: ") + e.what());
    }
  }

  struct Topic {
    std::string type;
    std::size_t messages = 0;
  };
  const std::map<std::string, Topic>& topics() const { return topics_; }
  const fs::path& path() const { return path_; }
  bool has(const std::string& topic) const { return topics_.count(topic) > 0; }
  const std::string& type_of(const std::string& topic) const { return topics_.at(topic).type; }

  std::vector<std::string> topics_of(const std::vector<std::string>& types) const {
    std::vector<std::string> out;
    for (const auto& [name, t] : topics_)
      if (std::find(types.begin(), types.end(), t.type) != types.end()) out.push_back(name);
    return out;
  }

  std::string where(const std::string& topic, std::size_t index) const {
    return path_.string() + " " + topic + " message " + std::to_string(index);
  }

  // Calls f(message, receive time, index) for each message of `topic`, in the bag's order;
  // `limit` 0 = all.
  template <class Msg, class F>
  void for_each(const std::string& topic, F&& f, std::size_t limit = 0) {
    std::size_t index = 0;
    try {
      rosbag::View view(bag_, rosbag::TopicQuery(topic));
      for (const rosbag::MessageInstance& m : view) {
        const auto msg = m.instantiate<Msg>();
        if (!msg)
          throw IoError(where(topic, index), "is a " + m.getDataType() + ", not a " +
                                                  ros::message_traits::DataType<Msg>::value());
        f(*msg, m.getTime(), index);
        if (++index == limit) break;
      }
    } catch (const IoError&) {
      throw;
    } catch (const ConfigError&) {
      throw;
    } catch (const std::exception& e) {
      throw IoError(where(topic, index), std::string("cannot be decoded: ") + e.what());
    }
  }

 private:
  fs::path path_;
  rosbag::Bag bag_;
  std::map<std::string, Topic> topics_;
};

Timestamp to_ns(const ros::Time& t) { return static_cast<Timestamp>(t.sec) * 1'000'000'000 + t.nsec; }

// The header stamp; the bag's receive time when the publisher left it 0 (a warning says so).
Timestamp message_time(const ros::Time& stamp, const ros::Time& received, const std::string& topic, DataReport& report) {
  if (!stamp.isZero()) return to_ns(stamp);
  report.warn(topic, "header stamp is 0: the bag's receive time is used");
  return to_ns(received);
}

// Sorts by time and keeps the first of equal times, counting both in the report.
template <class T>
void order_by_time(std::vector<T>& samples, const std::string& topic, DataReport& report) {
  const auto by_t = [](const T& a, const T& b) { return a.t < b.t; };
  if (!std::is_sorted(samples.begin(), samples.end(), by_t)) {
    report.warn(topic, "messages out of stamp order: sorted by stamp");
    std::stable_sort(samples.begin(), samples.end(), by_t);
  }
  const auto same_t = [](const T& a, const T& b) { return a.t == b.t; };
  const auto end = std::unique(samples.begin(), samples.end(), same_t);
  for (auto it = end; it != samples.end(); ++it) report.warn(topic, "message with a repeated stamp dropped");
  samples.erase(end, samples.end());
}

Vec3 vec(const geometry_msgs::Vector3& v) { return Vec3(v.x, v.y, v.z); }

// A quaternion of a message, normalised; nullopt when it is not close to unit length.
std::optional<Quat> unit_quaternion(const geometry_msgs::Quaternion& q) {
  const Quat r(q.w, q.x, q.y, q.z);
  const double n = r.norm();
  if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-3) return std::nullopt;
  return r.normalized();
}

SE3 pose_of(const geometry_msgs::Pose& p, const Quat& q) {
  return SE3(q, Vec3(p.position.x, p.position.y, p.position.z));
}

std::string strip_slash(std::string frame) {
  while (!frame.empty() && frame.front() == '/') frame.erase(frame.begin());
  return frame;
}

// ---------------------------------------------------------------------------------------------
// Topic choice

class TopicChooser {
 public:
  TopicChooser(BagFile& bag, const RosBagReadOptions& options) : bag_(bag), t_(options.topics) {
    if (!options.preset.empty()) apply_preset(options.preset);
    check_named();
    detect();
    for (std::string* role : {&t_.imu, &t_.gyro, &t_.accel, &t_.image, &t_.depth, &t_.camera_info, &t_.gps, &t_.mag,
                              &t_.groundtruth})
      if (*role == kNone) role->clear();
  }
  const RosBagTopics& topics() const { return t_; }

 private:
  void apply_preset(const std::string& preset) {
    for (const auto& [role, candidates] : ros_bag_preset(preset).roles) {
      std::string& slot = ros_bag_topic(t_, role);
      if (!slot.empty()) continue;
      for (const auto& c : candidates)
        if (bag_.has(c)) {
          slot = c;
          break;
        }
    }
    if (!t_.imu.empty()) t_.gyro.clear(), t_.accel.clear();  // a united IMU wins over two topics
  }

  void require_type(const std::string& role, const std::string& topic, const std::vector<std::string>& types) {
    if (topic.empty() || topic == kNone) return;
    if (!bag_.has(topic)) {
      std::vector<std::string> all;
      for (const auto& [name, t] : bag_.topics()) all.push_back(name + " [" + t.type + "]");
      throw IoError(bag_.path().string(), "topic " + topic + " (named for " + role + ") is not in the bag; its topics: " +
                                              (all.empty() ? "none" : join(all)));
    }
    const auto& type = bag_.type_of(topic);
    if (std::find(types.begin(), types.end(), type) == types.end())
      throw IoError(bag_.path().string(), "topic " + topic + " (named for " + role + ") is a " + type + ", not a " +
                                              join(types));
  }

  void check_named() {
    require_type("imu", t_.imu, {kImuType});
    require_type("gyro", t_.gyro, {kImuType});
    require_type("accel", t_.accel, {kImuType});
    if (t_.gyro == kNone) t_.gyro.clear();
    if (t_.accel == kNone) t_.accel.clear();
    if (t_.gyro.empty() != t_.accel.empty())
      throw IoError(bag_.path().string(), "gyro and accel topics come together (one is named, the other is not)");
    if (!t_.imu.empty() && t_.imu != kNone && !t_.gyro.empty())
      throw IoError(bag_.path().string(), "name either an imu topic or gyro + accel topics, not both");
    require_type("image", t_.image, {kImageType, kCompressedType});
    require_type("depth", t_.depth, {kImageType, kCompressedType});
    require_type("camera_info", t_.camera_info, {kCameraInfoType});
    require_type("gps", t_.gps, {kNavSatFixType});
    require_type("mag", t_.mag, {kMagType});
    require_type("groundtruth", t_.groundtruth, {kPoseType, kOdometryType});
    if (!t_.image.empty() && t_.image != kNone && image_kind(t_.image) != detail::RosImageKind::kIntensity)
      throw IoError(bag_.path().string(), "topic " + t_.image + " (named for image) does not hold intensity images");
    if (!t_.depth.empty() && t_.depth != kNone && image_kind(t_.depth) != detail::RosImageKind::kDepth)
      throw IoError(bag_.path().string(), "topic " + t_.depth + " (named for depth) does not hold depth images");
  }

  // The kind of an image topic, from its first message's encoding.
  detail::RosImageKind image_kind(const std::string& topic) {
    auto kind = detail::RosImageKind::kUnsupported;
    if (bag_.type_of(topic) == kImageType)
      bag_.for_each<sensor_msgs::Image>(
          topic, [&](const sensor_msgs::Image& m, const ros::Time&, std::size_t) { kind = detail::raw_image_kind(m.encoding); },
          1);
    else
      bag_.for_each<sensor_msgs::CompressedImage>(
          topic,
          [&](const sensor_msgs::CompressedImage& m, const ros::Time&, std::size_t) {
            kind = detail::compressed_image_kind(m.format);
          },
          1);
    return kind;
  }

  // The one candidate, or "" when there is none; several are an error naming them.
  std::string only(const std::string& role, const std::vector<std::string>& candidates, const std::string& what) {
    if (candidates.empty()) return "";
    if (candidates.size() == 1) return candidates.front();
    throw IoError(bag_.path().string(), "several " + what + " topics (" + join(candidates) + "); name the " + role +
                                            " topic with --topic " + role + "=TOPIC or a topics file (docs/ros.md)");
  }

  void detect() {
    if (t_.imu.empty() && t_.gyro.empty()) t_.imu = only("imu", bag_.topics_of({kImuType}), kImuType);
    if (t_.image.empty() || t_.depth.empty()) {
      std::vector<std::string> intensity, depth;
      for (const auto& topic : bag_.topics_of({kImageType, kCompressedType})) {
        if (topic == t_.image || topic == t_.depth) continue;
        const auto kind = image_kind(topic);
        if (kind == detail::RosImageKind::kIntensity) intensity.push_back(topic);
        if (kind == detail::RosImageKind::kDepth) depth.push_back(topic);
      }
      if (t_.image.empty()) t_.image = only("image", intensity, "intensity image");
      if (t_.depth.empty()) t_.depth = only("depth", depth, "depth image");
    }
    const std::string& camera_topic = (t_.image.empty() || t_.image == kNone) ? t_.depth : t_.image;
    if (t_.camera_info.empty() && camera_topic != kNone) t_.camera_info = camera_info_beside(camera_topic);
    if (t_.camera_info.empty()) t_.camera_info = only("camera_info", bag_.topics_of({kCameraInfoType}), kCameraInfoType);
    if (t_.gps.empty()) t_.gps = only("gps", bag_.topics_of({kNavSatFixType}), kNavSatFixType);
    if (t_.mag.empty()) t_.mag = only("mag", bag_.topics_of({kMagType}), kMagType);
    if (t_.groundtruth.empty())
      t_.groundtruth = only("groundtruth", bag_.topics_of({kPoseType, kOdometryType}), "pose or odometry");
  }

  // ROS drivers publish camera_info beside the image: /cam/color/image_raw(/compressed) ->
  // /cam/color/camera_info.
  std::string camera_info_beside(const std::string& image) {
    std::string ns = image;
    for (int up = 0; up < 2 && !ns.empty(); ++up) {
      ns = ns.substr(0, ns.find_last_of('/'));
      const std::string candidate = ns + "/camera_info";
      if (bag_.has(candidate) && bag_.type_of(candidate) == kCameraInfoType) return candidate;
    }
    return "";
  }

  BagFile& bag_;
  RosBagTopics t_;
};

// ---------------------------------------------------------------------------------------------
// Streams

std::vector<ImuSample> read_imu(BagFile& bag, const std::string& topic, DataReport& report, std::string& frame_id) {
  std::vector<ImuSample> out;
  bag.for_each<sensor_msgs::Imu>(topic, [&](const sensor_msgs::Imu& m, const ros::Time& received, std::size_t) {
    if (frame_id.empty()) frame_id = strip_slash(m.header.frame_id);
    ImuSample s;
    s.t = message_time(m.header.stamp, received, topic, report);
    s.gyro = vec(m.angular_velocity);
    s.accel = vec(m.linear_acceleration);
    if (!s.gyro.allFinite() || !s.accel.allFinite()) {
      report.warn(topic, "IMU message with a non-finite rate or acceleration skipped");
      return;
    }
    out.push_back(s);
  });
  order_by_time(out, topic, report);
  return out;
}

// Two IMU topics (gyro, accel) at their own rates: the acceleration is interpolated linearly at
// each gyro stamp; gyro samples outside the accelerometer's span are dropped.
std::vector<ImuSample> merge_gyro_accel(const std::vector<ImuSample>& gyro, const std::vector<ImuSample>& accel,
                                        const std::string& topic, DataReport& report) {
  std::vector<ImuSample> out;
  std::size_t j = 0;
  for (const auto& g : gyro) {
    while (j + 1 < accel.size() && accel[j + 1].t < g.t) ++j;
    if (accel.empty() || g.t < accel.front().t || g.t > accel.back().t || j + 1 >= accel.size()) {
      if (!accel.empty() && g.t == accel.back().t) {
        out.push_back({g.t, g.gyro, accel.back().accel, true});
        continue;
      }
      report.warn(topic, "gyro sample outside the accelerometer's time span dropped");
      continue;
    }
    const auto& a0 = accel[j];
    const auto& a1 = accel[j + 1];
    const double w = static_cast<double>(g.t - a0.t) / static_cast<double>(a1.t - a0.t);
    out.push_back({g.t, g.gyro, (1.0 - w) * a0.accel + w * a1.accel, true});
  }
  return out;
}

std::vector<GpsFix> read_gps(BagFile& bag, const std::string& topic, const RosBagReadOptions& options, DataReport& report) {
  std::vector<GpsFix> out;
  bag.for_each<sensor_msgs::NavSatFix>(topic, [&](const sensor_msgs::NavSatFix& m, const ros::Time& received, std::size_t) {
    if (!std::isfinite(m.latitude) || !std::isfinite(m.longitude) || std::abs(m.latitude) > 90 ||
        std::abs(m.longitude) > 180) {
      report.warn(topic, "fix without a valid latitude / longitude skipped");
      return;
    }
    GpsFix f;
    f.t = message_time(m.header.stamp, received, topic, report);
    f.latitude_deg = m.latitude;
    f.longitude_deg = m.longitude;
    // NavSatFix altitude is above the WGS 84 ellipsoid: no geoid separation to add.
    f.altitude_m = m.altitude;
    f.geoid_separation_m = 0.0;
    const int status = m.status.status;
    f.mode = status < sensor_msgs::NavSatStatus::STATUS_FIX ? GpsFixMode::kNoFix
             : std::isfinite(m.altitude)                    ? GpsFixMode::k3D
                                                            : GpsFixMode::k2D;
    f.quality = status < 0 ? 0 : status == sensor_msgs::NavSatStatus::STATUS_FIX ? 1 : 2;
    f.satellites = -1;
    f.hdop = std::numeric_limits<double>::quiet_NaN();
    Mat3 c;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) c(r, k) = m.position_covariance[static_cast<std::size_t>(3 * r + k)];
    const bool known = m.position_covariance_type != sensor_msgs::NavSatFix::COVARIANCE_TYPE_UNKNOWN;
    if (known && c.allFinite() && c.diagonal().minCoeff() > 0) {
      f.covariance_enu = 0.5 * (c + c.transpose());
    } else {
      std::ostringstream text;
      text << "fix without a usable position covariance: " << options.gps_unknown_sigma_m << " m horizontal, "
           << 2 * options.gps_unknown_sigma_m << " m vertical (1 sigma) assumed";
      report.warn(topic, text.str());
      const double s2 = options.gps_unknown_sigma_m * options.gps_unknown_sigma_m;
      f.covariance_enu = Vec3(s2, s2, 4 * s2).asDiagonal();
    }
    out.push_back(f);
  });
  order_by_time(out, topic, report);
  return out;
}

std::vector<MagSample> read_mag(BagFile& bag, const std::string& topic, DataReport& report) {
  std::vector<MagSample> out;
  bag.for_each<sensor_msgs::MagneticField>(topic, [&](const sensor_msgs::MagneticField& m, const ros::Time& received,
                                                      std::size_t) {
    MagSample s{message_time(m.header.stamp, received, topic, report), vec(m.magnetic_field)};
    if (!s.field.allFinite()) {
      report.warn(topic, "non-finite magnetic field skipped");
      return;
    }
    out.push_back(s);
  });
  order_by_time(out, topic, report);
  return out;
}

std::vector<GroundTruthState> read_groundtruth(BagFile& bag, const std::string& topic, DataReport& report) {
  std::vector<GroundTruthState> out;
  const auto add = [&](const std_msgs::Header& h, const ros::Time& received, const geometry_msgs::Pose& p,
                       const std::optional<Vec3>& v_child) {
    const auto& o = p.orientation;
    if (o.x == 0 && o.y == 0 && o.z == 0 && o.w == 0) {  // how ROS publishers say "no orientation"
      report.warn(topic, "pose without an orientation (all-zero quaternion) skipped");
      return;
    }
    const auto q = unit_quaternion(o);
    const Vec3 position(p.position.x, p.position.y, p.position.z);
    if (!q || !position.allFinite()) {
      report.warn(topic, "pose with a non-unit quaternion or a non-finite position skipped");
      return;
    }
    GroundTruthState g;
    g.t = message_time(h.stamp, received, topic, report);
    g.T_W_B = pose_of(p, *q);
    // nav_msgs/Odometry gives the twist in the child (body) frame.
    if (v_child && v_child->allFinite()) g.v_W = *q * *v_child;
    out.push_back(g);
  };
  if (bag.type_of(topic) == kPoseType)
    bag.for_each<geometry_msgs::PoseStamped>(topic, [&](const geometry_msgs::PoseStamped& m, const ros::Time& r, std::size_t) {
      add(m.header, r, m.pose, std::nullopt);
    });
  else
    bag.for_each<nav_msgs::Odometry>(topic, [&](const nav_msgs::Odometry& m, const ros::Time& r, std::size_t) {
      add(m.header, r, m.pose.pose, vec(m.twist.twist.linear));
    });
  order_by_time(out, topic, report);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Camera

CameraCalibration read_camera_info(BagFile& bag, const std::string& topic, DataReport& report, std::string& frame_id) {
  std::optional<CameraCalibration> first;
  bag.for_each<sensor_msgs::CameraInfo>(topic, [&](const sensor_msgs::CameraInfo& m, const ros::Time&, std::size_t i) {
    const std::string where = bag.where(topic, i);
    CameraCalibration c;
    c.name = kCamera;
    c.width = static_cast<int>(m.width);
    c.height = static_cast<int>(m.height);
    c.fx = m.K[0];
    c.fy = m.K[4];
    c.cx = m.K[2];
    c.cy = m.K[5];
    if (!(c.fx > 0 && c.fy > 0 && std::isfinite(c.cx) && std::isfinite(c.cy)) || c.width <= 0 || c.height <= 0)
      throw IoError(where, "camera_info has no usable intrinsics (K or size is zero: an uncalibrated camera)");
    const std::vector<double> d(m.D.begin(), m.D.end());
    const bool all_zero = std::all_of(d.begin(), d.end(), [](double v) { return v == 0.0; });
    if (all_zero) {
      c.distortion = DistortionModel::kNone;
    } else if (m.distortion_model == "plumb_bob" || m.distortion_model == "rational_polynomial") {
      // ROS's D is k1 k2 p1 p2 k3 [k4 k5 k6]; the rational terms must be zero to be radtan.
      if (d.size() < 4 || (d.size() > 5 && std::any_of(d.begin() + 5, d.end(), [](double v) { return v != 0.0; })))
        throw IoError(where, "distortion '" + m.distortion_model + "' with " + std::to_string(d.size()) +
                                 " coefficients is not radial-tangential (k1 k2 p1 p2 [k3])");
      c.distortion = DistortionModel::kRadialTangential;
      c.distortion_coeffs.assign(d.begin(), d.begin() + std::min<std::size_t>(d.size(), 5));
    } else if (m.distortion_model == "equidistant" && d.size() == 4) {
      c.distortion = DistortionModel::kEquidistant;
      c.distortion_coeffs = d;
    } else {
      throw IoError(where, "distortion model '" + m.distortion_model + "' with " + std::to_string(d.size()) +
                               " coefficients is not supported (plumb_bob, equidistant with 4)");
    }
    if (!first) {
      first = c;
      frame_id = strip_slash(m.header.frame_id);
    } else if (c.fx != first->fx || c.fy != first->fy || c.cx != first->cx || c.cy != first->cy ||
               c.width != first->width || c.height != first->height) {
      report.warn(topic, "camera_info changes during the bag: the first one is used");
    }
  });
  if (!first) throw IoError(bag.path().string(), "topic " + topic + " holds no camera_info message");
  return *first;
}

struct FrameSlot {
  std::string intensity_path, depth_path;
  Timestamp depth_dt = 0;  // |t_depth - t_frame| of the depth written
  bool has_depth = false;
};

class FrameWriter {
 public:
  FrameWriter(BagFile& bag, const RosBagTopics& topics, const RosBagReadOptions& options, DataReport& report)
      : bag_(bag), topics_(topics), options_(options), report_(report) {}

  // Writes the intensity images, then pairs and writes the depth images.
  std::map<Timestamp, FrameSlot> write() {
    if (!topics_.image.empty()) {
      fs::create_directories(options_.image_folder / "rgb");
      if (bag_.type_of(topics_.image) == kImageType)
        bag_.for_each<sensor_msgs::Image>(topics_.image, [&](const sensor_msgs::Image& m, const ros::Time& r, std::size_t i) {
          add_intensity(m.header, r, detail::decode_intensity(m, bag_.where(topics_.image, i)), i);
        });
      else
        bag_.for_each<sensor_msgs::CompressedImage>(
            topics_.image, [&](const sensor_msgs::CompressedImage& m, const ros::Time& r, std::size_t i) {
              add_intensity(m.header, r, detail::decode_intensity(m, bag_.where(topics_.image, i)), i);
            });
    }
    if (!topics_.depth.empty()) {
      fs::create_directories(options_.image_folder / "depth");
      window_ = pair_window();
      if (bag_.type_of(topics_.depth) == kImageType)
        bag_.for_each<sensor_msgs::Image>(topics_.depth, [&](const sensor_msgs::Image& m, const ros::Time& r, std::size_t i) {
          add_depth(m.header, r, detail::decode_depth(m, bag_.where(topics_.depth, i)), i);
        });
      else
        bag_.for_each<sensor_msgs::CompressedImage>(
            topics_.depth, [&](const sensor_msgs::CompressedImage& m, const ros::Time& r, std::size_t i) {
              add_depth(m.header, r, detail::decode_depth(m, bag_.where(topics_.depth, i)), i);
            });
      if (!topics_.image.empty())
        for (const auto& [t, slot] : frames_)
          if (!slot.has_depth) report_.warn(topics_.image, "image without a depth image within the pairing window");
    }
    return std::move(frames_);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& frame_id() const { return frame_id_; }

 private:
  std::string image_path(const char* folder, Timestamp t) const {
    return (options_.image_folder / folder / (std::string(kCamera) + "_" + std::to_string(t) + ".png")).string();
  }

  void check_size(int w, int h, const std::string& topic, std::size_t i, const char* what) {
    if (width_ == 0) {
      width_ = w;
      height_ = h;
      return;
    }
    if (w != width_ || h != height_)
      throw IoError(bag_.where(topic, i), std::string(what) + " is " + std::to_string(w) + "x" + std::to_string(h) +
                                              " but the camera's images are " + std::to_string(width_) + "x" +
                                              std::to_string(height_) +
                                              (std::string(what) == "depth image"
                                                   ? " (record depth aligned to the colour image, e.g. aligned_depth_to_color)"
                                                   : ""));
  }

  void add_intensity(const std_msgs::Header& h, const ros::Time& received, const ImageU8& image, std::size_t i) {
    const Timestamp t = message_time(h.stamp, received, topics_.image, report_);
    if (frame_id_.empty()) frame_id_ = strip_slash(h.frame_id);
    check_size(image.width, image.height, topics_.image, i, "image");
    if (frames_.count(t)) {
      report_.warn(topics_.image, "message with a repeated stamp dropped");
      return;
    }
    FrameSlot slot;
    slot.intensity_path = image_path("rgb", t);
    write_png(slot.intensity_path, image);
    frames_.emplace(t, slot);
  }

  // Half the median intensity period (or the option), so a depth image pairs with one frame only.
  Timestamp pair_window() const {
    if (options_.depth_pair_window_s > 0) return seconds_to_ns(options_.depth_pair_window_s);
    std::vector<Timestamp> periods;
    for (auto it = frames_.begin(); it != frames_.end() && std::next(it) != frames_.end(); ++it)
      periods.push_back(std::next(it)->first - it->first);
    if (periods.empty()) return seconds_to_ns(0.02);
    std::nth_element(periods.begin(), periods.begin() + static_cast<long>(periods.size() / 2), periods.end());
    return periods[periods.size() / 2] / 2;
  }

  void add_depth(const std_msgs::Header& h, const ros::Time& received, const detail::DepthMillimetres& depth,
                 std::size_t i) {
    const Timestamp t = message_time(h.stamp, received, topics_.depth, report_);
    if (depth.dropped > 0) report_.warn(topics_.depth, "depth pixels beyond 65.535 m set invalid");
    if (topics_.image.empty()) {  // depth-only bag: every depth image is a frame
      if (frame_id_.empty()) frame_id_ = strip_slash(h.frame_id);
      check_size(depth.image.width, depth.image.height, topics_.depth, i, "depth image");
      if (frames_.count(t)) {
        report_.warn(topics_.depth, "message with a repeated stamp dropped");
        return;
      }
      FrameSlot slot;
      slot.depth_path = image_path("depth", t);
      slot.has_depth = true;
      write_png(slot.depth_path, depth.image);
      frames_.emplace(t, slot);
      return;
    }
    auto best = frames_.end();
    auto it = frames_.lower_bound(t);
    if (it != frames_.end()) best = it;
    if (it != frames_.begin()) {
      auto before = std::prev(it);
      if (best == frames_.end() || t - before->first < best->first - t) best = before;
    }
    if (best == frames_.end() || std::abs(best->first - t) > window_) {
      report_.warn(topics_.depth, "depth image without an intensity image within the pairing window skipped");
      return;
    }
    check_size(depth.image.width, depth.image.height, topics_.depth, i, "depth image");
    FrameSlot& slot = best->second;
    const Timestamp dt = std::abs(best->first - t);
    if (slot.has_depth && slot.depth_dt <= dt) {
      report_.warn(topics_.depth, "second depth image for one frame skipped (the nearer one is kept)");
      return;
    }
    if (slot.has_depth) report_.warn(topics_.depth, "a nearer depth image replaces an earlier one of the same frame");
    slot.depth_path = image_path("depth", best->first);
    slot.depth_dt = dt;
    slot.has_depth = true;
    write_png(slot.depth_path, depth.image);
  }

  BagFile& bag_;
  const RosBagTopics& topics_;
  const RosBagReadOptions& options_;
  DataReport& report_;
  std::map<Timestamp, FrameSlot> frames_;
  Timestamp window_ = 0;
  int width_ = 0, height_ = 0;
  std::string frame_id_;
};

// T_B_C from the bag's transforms: a path between the IMU's and the camera's frames through
// /tf_static (then /tf), each edge used in either direction.
std::optional<SE3> extrinsics_from_tf(BagFile& bag, const std::string& body_frame, const std::string& camera_frame) {
  if (body_frame.empty() || camera_frame.empty()) return std::nullopt;
  if (body_frame == camera_frame) return SE3::identity();
  std::map<std::string, std::vector<std::pair<std::string, SE3>>> edges;  // frame -> (neighbour, T_frame_neighbour)
  std::set<std::pair<std::string, std::string>> seen;
  for (const char* topic : {"/tf_static", "/tf"}) {
    if (!bag.has(topic) || bag.type_of(topic) != kTfType) continue;
    bag.for_each<tf2_msgs::TFMessage>(topic, [&](const tf2_msgs::TFMessage& m, const ros::Time&, std::size_t) {
      for (const auto& tr : m.transforms) {
        const std::string parent = strip_slash(tr.header.frame_id), child = strip_slash(tr.child_frame_id);
        if (!seen.insert({parent, child}).second) continue;  // the first transform of each pair
        const auto q = unit_quaternion(tr.transform.rotation);
        if (!q) continue;
        const SE3 T(*q, vec(tr.transform.translation));
        edges[parent].push_back({child, T});
        edges[child].push_back({parent, T.inverse()});
      }
    });
  }
  std::map<std::string, SE3> reached{{body_frame, SE3::identity()}};
  std::deque<std::string> queue{body_frame};
  while (!queue.empty()) {
    const std::string f = queue.front();
    queue.pop_front();
    for (const auto& [next, T] : edges[f]) {
      if (reached.count(next)) continue;
      reached[next] = reached[f] * T;
      if (next == camera_frame) return reached[next];
      queue.push_back(next);
    }
  }
  return std::nullopt;
}

template <class T>
std::vector<Timestamp> stamps_of(const std::vector<T>& samples) {
  std::vector<Timestamp> stamps;
  for (const auto& s : samples) stamps.push_back(s.t);
  return stamps;
}

double median_rate_hz(const std::vector<Timestamp>& stamps) {
  if (stamps.size() < 2) return 0.0;
  std::vector<Timestamp> periods;
  for (std::size_t i = 1; i < stamps.size(); ++i) periods.push_back(stamps[i] - stamps[i - 1]);
  std::nth_element(periods.begin(), periods.begin() + static_cast<long>(periods.size() / 2), periods.end());
  const Timestamp p = periods[periods.size() / 2];
  return p > 0 ? 1.0 / ns_to_seconds(p) : 0.0;
}

}  // namespace

bool is_ros_bag(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[13] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == sizeof magic && std::string(magic, sizeof magic) == "#ROSBAG V2.0\n";
}

std::vector<RosBagTopicInfo> list_ros_bag_topics(const fs::path& path) {
  BagFile bag(path);
  std::vector<RosBagTopicInfo> out;
  for (const auto& [name, t] : bag.topics()) out.push_back({name, t.type, t.messages});
  return out;
}

Recording read_ros_bag(const fs::path& path, const RosBagReadOptions& options) {
  BagFile bag(path);
  const TopicChooser chooser(bag, options);
  const RosBagTopics& topics = chooser.topics();
  Recording r;
  r.path = path.string();
  r.format = "ros-bag";

  std::string imu_frame;
  if (!topics.imu.empty()) {
    r.imu = read_imu(bag, topics.imu, r.report, imu_frame);
  } else if (!topics.gyro.empty()) {
    std::string accel_frame;
    const auto gyro = read_imu(bag, topics.gyro, r.report, imu_frame);
    const auto accel = read_imu(bag, topics.accel, r.report, accel_frame);
    r.imu = merge_gyro_accel(gyro, accel, topics.gyro, r.report);
  }
  if (!topics.gps.empty()) r.gps = read_gps(bag, topics.gps, options, r.report);
  if (!topics.mag.empty()) r.mag = read_mag(bag, topics.mag, r.report);
  if (!topics.groundtruth.empty()) r.groundtruth = read_groundtruth(bag, topics.groundtruth, r.report);

  const bool has_images = !topics.image.empty() || !topics.depth.empty();
  if (has_images && options.image_folder.empty()) {
    for (const auto* topic : {&topics.image, &topics.depth})
      if (!topic->empty())
        r.report.warn(*topic, std::to_string(bag.topics().at(*topic).messages) +
                                  " image messages not extracted (navaid convert writes them as frames)");
  } else if (has_images) {
    std::string camera_frame;
    std::optional<CameraCalibration> camera;
    if (!topics.camera_info.empty()) camera = read_camera_info(bag, topics.camera_info, r.report, camera_frame);
    FrameWriter writer(bag, topics, options, r.report);
    const auto frames = writer.write();
    if (camera_frame.empty()) camera_frame = writer.frame_id();
    for (const auto& [t, slot] : frames) {
      RgbdFrame f;
      f.t = t;
      f.index = r.frames.size();
      f.camera = kCamera;
      f.intensity_path = slot.intensity_path;
      f.depth_path = slot.depth_path;
      f.depth_png_scale_m = kNavaidDepthScaleM;
      r.frames.push_back(std::move(f));
    }
    if (camera) {
      if (writer.width() != 0 && (writer.width() != camera->width || writer.height() != camera->height))
        throw IoError(path.string(), "camera_info on " + topics.camera_info + " is " + std::to_string(camera->width) +
                                         "x" + std::to_string(camera->height) + " but the images are " +
                                         std::to_string(writer.width()) + "x" + std::to_string(writer.height()));
      camera->rate_hz = median_rate_hz(stamps_of(r.frames));
      if (const auto T = extrinsics_from_tf(bag, imu_frame, camera_frame)) {
        camera->T_B_C = *T;
      } else if (!r.imu.empty()) {
        r.report.warn(topics.camera_info, "no transform between the IMU frame '" + imu_frame + "' and the camera frame '" +
                                              camera_frame + "' in /tf_static or /tf: T_B_C is identity (give a Kalibr "
                                              "camchain for the real one)");
      }
      if (!options.preset.empty()) {
        const RosBagPreset preset = ros_bag_preset(options.preset);
        camera->depth_min_m = preset.depth_min_m;
        camera->depth_max_m = preset.depth_max_m;
        camera->depth_baseline_m = preset.depth_baseline_m;
        camera->depth_disparity_sigma_px = preset.depth_disparity_sigma_px;
      }
      r.calibration.cameras.push_back(*camera);
    } else {
      r.report.warn(topics.image.empty() ? topics.depth : topics.image,
                    "no camera_info topic: the camera's intrinsics are unknown (give a Kalibr camchain)");
    }
  }
  // No noise densities in a bag: calibration.imu comes from a Kalibr IMU file (navaid convert).
  if (!r.gps.empty()) r.calibration.gps_rate_hz = median_rate_hz(stamps_of(r.gps));
  if (!r.mag.empty()) r.calibration.mag_rate_hz = median_rate_hz(stamps_of(r.mag));
  return r;
}

}  // namespace navaid::io
