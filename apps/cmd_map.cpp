// navaid map: the semantic voxel map of a recording, with the poses of a navaid run folder (the
// estimator's, covariance and mode included) or the recording's ground truth (map_session.hpp
// writes the map folder; docs/mapping.md).
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "input_option.hpp"
#include "map_poses.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/experiments/map_session.hpp"
#include "navaid/runtime/config_schema.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/experiments/progress.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::cli {

using experiments::Progress;
using experiments::MapSession;
using experiments::MapSessionOptions;
using experiments::recording_start;
using experiments::groundtruth_poses;


namespace {

struct MapArgs {
  std::filesystem::path recording, run, out, config_file;
  std::string poses = "run";
  std::vector<std::string> overrides;
  double snapshot_every_s = 1.0;
  double png_every_s = 5.0;
  bool no_quality = false;
};

void run_map(const MapArgs& a) {
  if (a.recording.empty()) throw UsageError("--recording is required");
  if (a.out.empty()) throw UsageError("--out is required");
  if (a.poses == "run" && a.run.empty()) throw UsageError("--run is required (or --poses groundtruth)");
  if (!(a.snapshot_every_s > 0)) throw UsageError("--snapshot-every must be positive");
  if (!(a.png_every_s >= 0)) throw UsageError("--png-every must be 0 or positive");
  const Config config = a.config_file.empty() ? Config::parse("{}", "<defaults>", a.overrides)
                                              : Config::load(a.config_file, a.overrides);
  const ConfigReads reads(config);
  const mapping::MapperConfig mapper_config = mapping::read_mapper_config(config);
  MapSessionOptions options{a.snapshot_every_s, a.png_every_s, !a.no_quality, 0};
  runtime::MappingStageOptions stage_options = runtime::read_mapping_stage_options(config);
  config.reject_unknown_keys(mapping::mapper_config_schema().add(runtime::mapping_stage_options_schema()));

  const io::Recording recording = read_camera_recording(a.recording, "RGB-D frames");
  if (recording.calibration.cameras.empty()) throw Error(a.recording.string() + ": no camera in the calibration");
  const CameraCalibration& camera = recording.calibration.cameras.front();
  std::vector<RgbdFrame> frames;
  for (const auto& f : recording.frames)
    if (f.camera == camera.name) frames.push_back(f);
  if (frames.empty())
    throw Error(a.recording.string() + ": no image frames of camera '" + camera.name +
                "' (a feature-level recording has nothing to map)");

  FramePoses poses;
  const std::string poses_source =
      a.poses == "groundtruth" ? a.recording.string() + " (ground truth)" : (a.run / "estimates.csv").string();
  if (a.poses == "groundtruth") {
    poses = poses_from_groundtruth(recording, frames, camera.time_offset_s);
  } else {
    const auto estimates_file = a.run / "estimates.csv";
    poses = poses_from_estimates(frames, experiments::read_estimates_csv(estimates_file), estimates_file);
  }

  options.frames_total = frames.size();
  stage_options.network_start = recording_start(recording);
  if (a.poses == "run") options.align_to = groundtruth_poses(recording);
  runtime::MappingStage stage(mapper_config, camera, stage_options);
  MapSession session(stage, a.recording, a.out, options);
  Progress progress("mapping", frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    progress.update(i);
    if (!poses[i]) {
      session.add_without_pose();
      continue;
    }
    try {
      session.record(frames[i], *poses[i], stage.add(frames[i], *poses[i]));
    } catch (const IoError&) {
      throw;  // names its own file (an image)
    } catch (const Error& e) {
      throw Error(poses_source + ": " + e.what());  // a bad covariance or pose: say where it came from
    }
  }
  progress.finish();
  nlohmann::ordered_json head;
  head["recording"] = std::filesystem::absolute(a.recording).string();
  head["poses"] = a.poses == "groundtruth" ? std::string("groundtruth")
                                           : std::filesystem::absolute(a.run / "estimates.csv").string();
  const auto summary = session.finish(head);
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());
  const auto& f = summary["frames"];
  std::cout << fmt::format("mapped {} of {} frames ({} not localised, {} too uncertain, {} without depth, {} without "
                           "pose); {:.1f} ms median per mapped frame\n",
                           f["mapped"].get<std::size_t>(), f["total"].get<std::size_t>(),
                           f["not_localised"].get<std::size_t>(), f["too_uncertain"].get<std::size_t>(),
                           f["no_depth"].get<std::size_t>(), f["without_pose"].get<std::size_t>(),
                           summary["time_per_mapped_frame_ms"]["median"].get<double>());
  if (summary.contains("network")) {
    const auto& n = summary["network"];
    std::cout << fmt::format("network: {} of {} outages detected; {} frames mapped geometry only (network.csv)\n",
                             n["outages_detected"].get<std::size_t>(), n["outages_configured"].get<std::size_t>(),
                             n["frames_geometry_only"].get<std::size_t>());
  }
  if (summary.contains("quality")) {
    const auto& q = summary["quality"];
    std::cout << fmt::format("quality: occupancy precision {:.3f}, recall {:.3f}, F1 {:.3f}; semantic accuracy {:.3f}; "
                             "obstacles detected {} of {}",
                             q["occupancy"]["precision"].get<double>(), q["occupancy"]["recall"].get<double>(),
                             q["occupancy"]["f1"].get<double>(), q["semantic_accuracy"].get<double>(),
                             q["obstacles_detected"].get<std::size_t>(), q["obstacles_in_reach"].get<std::size_t>());
    if (q["on_path_obstacles_in_reach"].get<std::size_t>() > 0)
      std::cout << fmt::format(" ({} of {} on the path)", q["on_path_obstacles_detected"].get<std::size_t>(),
                               q["on_path_obstacles_in_reach"].get<std::size_t>());
    std::cout << "\n";
  }
}

}  // namespace

void add_map_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("map", "Build the semantic voxel map of a recording from a run's poses or ground truth");
  auto a = std::make_shared<MapArgs>();
  cmd->add_option("--recording", a->recording, "Recording with RGB-D frames (navaid, TUM RGB-D or EuRoC)");
  cmd->add_option("--run", a->run, "navaid run folder whose estimates.csv gives the poses");
  cmd->add_option("--poses", a->poses, "Where poses come from")
      ->check(CLI::IsMember({"run", "groundtruth"}))
      ->capture_default_str();
  cmd->add_option("--out", a->out, "Map folder to write (map.ot, map-color.ot, map.ply, topview.png, summary.json)");
  cmd->add_option("--config", a->config_file, "YAML configuration (mapping.* keys, docs/mapping.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set mapping.map.fusion=bayes (repeatable)");
  cmd->add_option("--snapshot-every", a->snapshot_every_s,
                  "Seconds of recording between map snapshots (top view, quality)")
      ->capture_default_str();
  cmd->add_option("--png-every", a->png_every_s,
                  "Seconds of recording between 2D-map PNGs in snapshots/ (0: only the final ones)")
      ->capture_default_str();
  cmd->add_flag("--no-quality", a->no_quality,
                "Skip the comparison with the simulated world (its bookkeeping grows with the route)");
  cmd->callback([a] { run_map(*a); });
}

}  // namespace navaid::cli
