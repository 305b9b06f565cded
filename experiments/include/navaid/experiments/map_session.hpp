#pragma once
// What a run keeps of a mapping stage (runtime/mapping_stage.hpp), shared by `navaid map` (poses
// from a run folder or ground truth), `navaid run --set mapping.enabled=true` and a device run
// (poses as the estimator makes them): each mapped frame's timing, obstacle scan and network
// changes, snapshots of the map (top view, quality against a simulated world), and the map folder
// (map.ot, map-color.ot, map.ply, topview.png, timing.csv, summary.json).
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
#include "navaid/runtime/mapping_stage.hpp"

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
};

/// Where mapping.network.outages count from: the recording's earliest IMU sample, frame, GPS fix
/// or magnetometer sample (0 for an empty recording).
Timestamp recording_start(const io::Recording& recording);

/// The simulated world behind a recording written by navaid simulate (its simulation.yaml), if any.
std::optional<simulation::Scenario> recording_scenario(const std::filesystem::path& recording);

/// The recording's ground truth as stamped poses (for MapSessionOptions::align_to).
std::vector<io::StampedPose> groundtruth_poses(const io::Recording& recording);

class MapSession {
 public:
  /// Keeps what `stage` maps; `recording_dir`: where the recording lives (its simulation.yaml,
  /// when present, gives the world for the quality metrics). Creates `out`.
  MapSession(const runtime::MappingStage& stage, const std::filesystem::path& recording_dir,
             const std::filesystem::path& out, const MapSessionOptions& options);
  ~MapSession();

  /// One frame the stage has just mapped (`mapped`: what add() returned).
  void record(const RgbdFrame& frame, const StateEstimate& estimate, const runtime::MappedFrame& mapped);
  /// A frame that has no pose (counted).
  void add_without_pose() { ++no_pose_; }

  /// Writes the map files and summary.json (with `extra` merged at the top); returns the summary.
  nlohmann::ordered_json finish(const nlohmann::ordered_json& extra);

 private:
  /// height, undulation, collision, cost and ESDF PNGs of the last mapped frame's window.
  void write_layer_pngs(const std::filesystem::path& dir, const std::string& prefix) const;
  void write_obstacle_row(const mapping::ObstacleScan& scan);

  const runtime::MappingStage& stage_;
  std::ofstream obstacle_csv_;
  std::ofstream network_csv_;
  /// The link's changes as system events on the recording's clock (system_events.csv, for navaid cues).
  std::vector<interaction::GuidanceTimelineEntry> network_events_;
  std::filesystem::path out_;
  MapSessionOptions options_;
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
