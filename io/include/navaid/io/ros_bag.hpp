#pragma once
// ROS 1 bags (format 2.0, uncompressed, bz2 or lz4 chunks) as recordings, read with Debian's
// rosbag_storage (thirdparty-notes/rosbag.md). ROS headers stay in io/src. docs/ros.md.
//
// Messages read, by role:
//   imu          sensor_msgs/Imu (or two Imu topics, gyro + accel, merged at the gyro's stamps)
//   image        sensor_msgs/Image (mono8, rgb8, bgr8, rgba8, bgra8) or CompressedImage (jpeg, png)
//   depth        sensor_msgs/Image (16UC1 / mono16 millimetres, 32FC1 metres) or CompressedImage
//                (png, compressedDepth 16UC1 or 32FC1)
//   camera_info  sensor_msgs/CameraInfo (plumb_bob / equidistant; intrinsics of the image)
//   gps          sensor_msgs/NavSatFix     mag  sensor_msgs/MagneticField
//   groundtruth  geometry_msgs/PoseStamped or nav_msgs/Odometry
// Times are the messages' header stamps. A role left unnamed is found by message type when the bag
// has exactly one candidate topic; several candidates are an error that lists them; "none" leaves
// a role out.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/time.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::io {

/// The topic of each role; empty = find by message type, "none" = leave the role out.
struct RosBagTopics {
  std::string imu, gyro, accel, image, depth, camera_info, gps, mag, groundtruth;
};

/// The roles in the order above, with their names as accepted by set_ros_bag_topic.
std::vector<std::string_view> ros_bag_roles();
/// The topic of a role by name ("imu", "image", ...); ConfigError for an unknown role.
std::string& ros_bag_topic(RosBagTopics& topics, std::string_view role);
/// Sets one role by name ("imu", "image", ...); UsageError-like ConfigError for an unknown role.
void set_ros_bag_topic(RosBagTopics& topics, std::string_view role, const std::string& topic);
/// A driver's topic names and what its datasheet says of the depth camera.
struct RosBagPreset {
  /// Role -> candidate topics; the first one present in the bag is used.
  std::vector<std::pair<std::string, std::vector<std::string>>> roles;
  double depth_min_m = 0, depth_max_m = 0;  ///< working range, 0 when the preset does not fix the model
  double depth_baseline_m = 0;              ///< stereo baseline
  double depth_disparity_sigma_px = 0;      ///< subpixel disparity noise (1 sigma)
};
/// "realsense" (realsense2_camera, ROS 1: colour, depth aligned to it, the united /camera/imu or
/// the separate gyro / accel topics), "realsense-d435i" and "realsense-d455" (the same topics plus
/// the model's baseline), "structure-core" (Occipital's driver).
std::vector<std::string> ros_bag_preset_names();
/// Throws ConfigError naming the preset when unknown.
RosBagPreset ros_bag_preset(const std::string& name);
/// Reads a topics file: a YAML map role -> topic, or `preset: NAME` plus overrides. ConfigError
/// naming the file and key for an unknown role or a non-string value.
struct RosBagTopicChoice {
  RosBagTopics topics;
  std::string preset;  ///< empty = none
};
RosBagTopicChoice read_ros_bag_topics_file(const std::filesystem::path& path);

struct RosBagTopicInfo {
  std::string topic;
  std::string type;  ///< e.g. "sensor_msgs/Imu"
  std::size_t messages = 0;
};
/// The bag's topics sorted by name (no message is decoded).
std::vector<RosBagTopicInfo> list_ros_bag_topics(const std::filesystem::path& bag);

/// True when the file starts with the ROS bag 2.0 magic line.
bool is_ros_bag(const std::filesystem::path& path);

struct RosBagReadOptions {
  RosBagTopics topics;
  std::string preset;  ///< fills roles left empty, before detection by type
  /// Folder of the navaid recording being written: frame images go to its rgb/ and depth/ under
  /// the names the navaid writer gives them (write with images_in_place). Empty: image messages
  /// are counted in the report but no frame is produced.
  std::filesystem::path image_folder;
  /// A depth image is paired with the intensity image nearest in time within this window; 0 means
  /// half the median intensity period.
  double depth_pair_window_s = 0.0;
  /// GPS fixes whose covariance type is unknown get this 1-sigma [m] (horizontal; vertical 2x).
  double gps_unknown_sigma_m = 5.0;
};

/// Reads the chosen topics into a recording (format "ros-bag"). Camera intrinsics come from
/// CameraInfo; T_B_C from /tf_static (or /tf) when the IMU's and the camera's frames are connected
/// there, identity otherwise (a warning says so); no IMU noise is in a bag, so calibration.imu is
/// left empty (give a Kalibr IMU file). Throws IoError naming the bag (and topic) for unreadable
/// bags, missing or mistyped topics, unsupported encodings and inconsistent images.
Recording read_ros_bag(const std::filesystem::path& bag, const RosBagReadOptions& options = {});

}  // namespace navaid::io

namespace navaid::io {

/// A bag made into a navaid recording: the reader's options plus what a bag cannot hold.
struct RosBagConversion {
  RosBagReadOptions read;
  /// Kalibr camchain-imucam: cam0's intrinsics, distortion, T_cam_imu and time shift replace what
  /// CameraInfo and /tf_static gave (its resolution must match the images).
  std::filesystem::path camchain;
  /// Kalibr IMU file: the noise densities the estimator needs (a bag has none).
  std::filesystem::path imu_noise;
  /// The depth camera's working range [m] (a bag has none; a model's preset gives its datasheet
  /// range). Without one the front end leaves depth out, and a warning says so.
  double depth_min_m = 0, depth_max_m = 0;
  /// Replace the recording files in a non-empty output folder (old frame images are removed).
  bool overwrite = false;
};

/// Reads `bag` and writes it as a navaid recording into `folder`, frame images extracted once;
/// the ENU origin is the first 3D fix. Returns the recording as written (paths inside `folder`).
/// IoError when the folder is not empty (without overwrite) or the bag has frames but neither
/// camera_info nor a camchain; Kalibr files fail as read_kalibr_camchain / read_kalibr_imu do.
Recording convert_ros_bag(const std::filesystem::path& bag, const std::filesystem::path& folder,
                          const RosBagConversion& conversion);

}  // namespace navaid::io
