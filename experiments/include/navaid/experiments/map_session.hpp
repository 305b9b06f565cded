#pragma once
// One mapping session over a recording's frames, shared by `navaid map` (poses from a run folder
// or ground truth) and `navaid run --set mapping.enabled=true` (poses as the estimator makes
// them): maps each frame, snapshots the map (top view, quality against a simulated world), and
// writes the map folder (map.ot, map-color.ot, map.ply, topview.png, timing.csv, summary.json).
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/evaluation/map_quality.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "navaid/mapping/map_top_view.hpp"
#include "navaid/mapping/mapper.hpp"
#include "navaid/mapping/obstacle_pipeline.hpp"
#include "navaid/mapping/segmentation_link.hpp"

namespace navaid::experiments {

struct MapSessionOptions {
  double snapshot_every_s = 1.0;  ///< recording seconds between snapshots (top view, quality)
  double png_every_s = 5.0;       ///< recording seconds between 2D-map PNGs (snapshots/); 0: only the last
  bool quality = true;            ///< compare with the simulated world when the recording has one
  std::size_t frames_total = 0;   ///< for the memory read-outs at 25 / 50 / 75 / 100 % of the route
  /// Estimated poses: the recording's ground truth, to put the map into the simulated world for
  /// the quality metrics. Two alignments: at every snapshot the one that puts the current estimate
  /// onto the truth ("quality": the map as the user uses it, around where they are, charged with
  /// the drift within the window), and the one of the first mapped frame ("quality_global": all the
  /// drift since the start). Empty: the poses are in the world's frame already (ground truth).
  std::vector<io::StampedPose> align_to = {};
  /// mapping.obstacles.enabled: also run the BYU obstacle pipeline on every frame with a pose and
  /// write obstacle_scan.csv (its config: the other mapping.obstacles.* keys).
  std::optional<mapping::ObstaclePipelineConfig> obstacles = std::nullopt;
  double obstacle_prior_camera_height_m = 0.8;  ///< the prior T_U_C's height (cane mount)
  int obstacle_pixel_stride = 1;                ///< the thesis uses every pixel (its voxel grid thins them)
  /// mapping.network.*: the simulated cloud segmentation server (eLabrador's edge-cloud split).
  /// Frames whose labels the link does not deliver are mapped with geometry only; the link's
  /// changes go to network.csv. Absent: every frame keeps its labels.
  std::optional<mapping::SegmentationLinkConfig> network = std::nullopt;
  Timestamp network_start = 0;  ///< the recording start the outages are relative to
};

/// The obstacle options of a configuration: mapping.obstacles.enabled (false) and
/// mapping.obstacles.prior_camera_height_m (0.8 m), mapping.obstacles.pixel_stride (1) besides the
/// pipeline's own keys.
void read_obstacle_options(const Config& config, MapSessionOptions& options);
/// The options of a map session built as the estimates come (navaid run, a device, a trial): the
/// defaults with the obstacle options and mapping.network.* of `config`.
MapSessionOptions read_map_session_options(const Config& config);

/// Where mapping.network.outages count from: the recording's earliest IMU sample, frame, GPS fix
/// or magnetometer sample (0 for an empty recording).
Timestamp recording_start(const io::Recording& recording);

/// The simulated world behind a recording written by navaid simulate (its simulation.yaml), if any.
std::optional<simulation::Scenario> recording_scenario(const std::filesystem::path& recording);

/// The recording's ground truth as stamped poses (for MapSessionOptions::align_to).
std::vector<io::StampedPose> groundtruth_poses(const io::Recording& recording);

class MapSession {
 public:
  /// `recording_dir`: where the recording lives (its simulation.yaml, when present, gives the world
  /// for the quality metrics). Creates `out`.
  MapSession(const mapping::MapperConfig& config, const CameraCalibration& camera,
             const std::filesystem::path& recording_dir, const std::filesystem::path& out,
             const MapSessionOptions& options);
  ~MapSession();

  /// Maps one frame of the session's camera (images not loaded: loaded and freed here).
  void add(const RgbdFrame& frame, const StateEstimate& estimate);
  /// A frame that has no pose (counted).
  void add_without_pose() { ++no_pose_; }

  /// Writes the map files and summary.json (with `extra` merged at the top); returns the summary.
  nlohmann::ordered_json finish(const nlohmann::ordered_json& extra);

  const mapping::Mapper& mapper() const { return mapper_; }
  /// The obstacle scan of the last frame that had one (mapping.obstacles.enabled).
  const std::optional<mapping::ObstacleScan>& last_obstacle_scan() const { return last_scan_; }
  /// Network changes not yet taken (mapping.network.*), as system events for the cues.
  std::vector<interaction::GuidanceTimelineEntry> take_system_events();

 private:
  /// height, undulation, collision, cost and ESDF PNGs of the last mapped frame's window.
  void write_layer_pngs(const std::filesystem::path& dir, const std::string& prefix) const;

  /// The obstacle scan of one frame (its depth loaded) at the estimate's attitude.
  void scan_obstacles(const RgbdFrame& frame, const StateEstimate& estimate);

  mapping::MapperConfig config_;
  CameraCalibration camera_;
  std::optional<mapping::ObstaclePipeline> obstacles_;
  std::ofstream obstacle_csv_;
  std::optional<mapping::SegmentationLink> link_;
  std::ofstream network_csv_;
  /// The same changes as system events on the recording's clock (system_events.csv, for navaid cues).
  std::vector<interaction::GuidanceTimelineEntry> network_events_;
  std::size_t network_events_taken_ = 0;
  std::optional<mapping::ObstacleScan> last_scan_;
  std::size_t geometry_only_ = 0;  ///< frames mapped without labels because the link was down
  std::filesystem::path out_;
  MapSessionOptions options_;
  mapping::Mapper mapper_;
  mapping::MapTopView top_view_;
  std::optional<simulation::Scenario> scenario_;
  std::unique_ptr<evaluation::MapQualityAccumulator> quality_, quality_global_;
  std::ofstream timing_;
  std::vector<double> cloud_ms_, insert_ms_, layers_ms_, esdf_ms_, total_ms_;
  nlohmann::ordered_json memory_ = nlohmann::ordered_json::array();
  std::size_t frames_seen_ = 0, no_pose_ = 0, next_quarter_ = 1;
  std::optional<Timestamp> last_snapshot_, last_png_;
  std::size_t pngs_ = 0;
  bool aligned_ = false;
};

}  // namespace navaid::experiments
