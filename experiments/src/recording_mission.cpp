#include "navaid/experiments/recording_mission.hpp"

#include <algorithm>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/map_session.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/io/targets_csv.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/path_guidance.hpp"
#include "navaid/simulation/osm_export.hpp"

namespace navaid::experiments {
namespace {

using runtime::DeviceSpec;
using runtime::GuidanceKind;

runtime::RouteMission route_mission(const DeviceSpec& spec, const io::Recording& recording,
                                    const std::filesystem::path& recording_dir, const std::filesystem::path& out) {
  if (!recording.origin)
    throw Error(recording_dir.string() + ": no geodetic origin; device " + spec.name +
                " maps its route into the estimator's ENU frame at the recording's origin");
  std::filesystem::path osm = spec.route_osm;
  std::optional<planning::GeoPoint> from, to, face;
  if (spec.route_to) to = planning::GeoPoint{spec.route_to->first, spec.route_to->second};
  if (spec.route_face) face = planning::GeoPoint{spec.route_face->first, spec.route_face->second};
  if (osm.empty()) {
    // A simulated recording: its scenario's streets as OSM, and its path's ends.
    const auto scenario = recording_scenario(recording_dir);
    if (!scenario) throw Error(recording_dir.string() + ": not a simulated recording; set device.route.osm");
    const simulation::OsmExport e = simulation::export_osm(*scenario);
    simulation::write_osm_export(e, out / "route");
    osm = out / "route" / "map.osm";
    from = planning::GeoPoint{e.truth.start_lat_deg, e.truth.start_lon_deg};
    if (!to) to = planning::GeoPoint{e.truth.goal_lat_deg, e.truth.goal_lon_deg};
    if (!face && !e.truth.landmark_name.empty()) face = planning::GeoPoint{e.truth.landmark_lat_deg, e.truth.landmark_lon_deg};
  } else if (!recording.gps.empty()) {
    from = planning::GeoPoint{recording.gps.front().latitude_deg, recording.gps.front().longitude_deg};
  }
  if (!from || !to) throw Error("device " + spec.name + ": the route needs a start (GPS) and device.route.to");
  return {planning::load_osm_foot_graph(osm), osm.string(), *from, *to, face, *recording.origin};
}

/// The path's end from the true pose at the moment guidance starts, in that pose's (yaw-only)
/// frame: what the simulated user says the goal is.
runtime::WalkingGoal walking_goal(const DeviceSpec& spec, const io::Recording& recording,
                                  const std::filesystem::path& recording_dir) {
  const auto scenario = recording_scenario(recording_dir);
  if (!scenario || recording.groundtruth.empty())
    throw Error(recording_dir.string() + ": device " + spec.name +
                " needs a goal: set device.goal_start_frame_m=FORWARD,LEFT");
  const mapping::Vec2 path_end_W = scenario->path.back();
  return [path_end_W, truth = recording.groundtruth](Timestamp t) {
    const auto it = std::lower_bound(truth.begin(), truth.end(), t,
                                     [](const GroundTruthState& g, Timestamp v) { return g.t < v; });
    const GroundTruthState& g = it == truth.end() ? truth.back() : *it;
    const mapping::Vec2 rel = Eigen::Rotation2Dd(-planning::body_yaw(g.T_W_B)) * (path_end_W - g.T_W_B.t.head<2>());
    return std::make_pair(rel.x(), rel.y());
  };
}

int target_tag_id(const DeviceSpec& spec, const Config& config, const std::filesystem::path& recording_dir) {
  const std::string family = planning::read_apriltag_detector_config(config).family;
  const auto file = recording_dir / io::kTargetsCsv;
  if (std::filesystem::exists(file))
    for (const auto& t : io::read_targets_csv(file))
      if (t.tag_family == family) return t.tag_id;
  throw Error(recording_dir.string() + ": device " + spec.name + " guides the hand to a tagged object: set " +
              "device.tag_id (the recording has no targets.csv with a " + family + " tag)");
}

}  // namespace

runtime::DeviceMission recording_mission(const DeviceSpec& spec, const Config& config, const io::Recording& recording,
                                         const std::filesystem::path& recording_dir, const std::filesystem::path& out) {
  runtime::DeviceMission mission;
  switch (spec.guidance) {
    case GuidanceKind::kRoute:
      mission.route = route_mission(spec, recording, recording_dir, out);
      mission.place = runtime::street_places(*mission.route);
      break;
    case GuidanceKind::kWalkingPath:
      if (!spec.goal_start_frame_m) mission.walking_goal = walking_goal(spec, recording, recording_dir);
      break;
    case GuidanceKind::kHandTarget:
      if (!config.has("device.tag_id")) mission.tag_id = target_tag_id(spec, config, recording_dir);
      break;
    case GuidanceKind::kObstacleRumble: break;
  }
  return mission;
}

std::vector<TimedVoiceCommand> read_voice_commands(const std::filesystem::path& file) {
  std::vector<TimedVoiceCommand> out;
  for (const interaction::GuidanceTimelineEntry& entry : interaction::read_guidance_timeline_csv(file)) {
    const auto* e = std::get_if<interaction::SystemEvent>(&entry);
    if (!e || e->kind != interaction::SystemEventKind::kVoiceCommand)
      throw IoError(file.string(), "holds an entry that is no voice_command (at t = " +
                                       std::to_string(interaction::entry_time(entry)) + " ns)");
    const auto command = interaction::voice_command_from_words(e->value);
    if (!command)
      throw IoError(file.string(), "'" + e->value + "' is no voice command (go to <place>, repeat, where am i, "
                                   "stop guidance, not understood)");
    out.emplace_back(e->t, *command);
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

}  // namespace navaid::experiments
