// navaid simulate: walk a scenario with a mounted sensor rig and write a navaid recording with
// ground truth (docs/simulate.md).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <fstream>
#include <utility>
#include <memory>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command_schemas.hpp"
#include "commands.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/euroc.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "navaid/simulation/recorded_motion.hpp"
#include "navaid/simulation/simulator.hpp"
#include "navaid/experiments/progress.hpp"

namespace navaid::cli {

using experiments::Progress;


namespace {

struct SimulateArgs {
  std::string scenario, mount;
  std::optional<long long> seed;
  std::filesystem::path out, config_file, cache, from_recording, imu_calibration, camera_calibration;
  std::vector<std::string> overrides;
  int threads = 0;
  bool overwrite = false, list = false;
};

void list_scenarios() {
  for (const auto& name : simulation::scenario_names()) {
    const auto s = simulation::make_scenario(name);
    std::cout << fmt::format("{:<16} {}\n", name, s.description);
  }
}

Config build_config(const SimulateArgs& a) {
  // Command-line flags are overrides too, applied after the file and before --set.
  std::vector<std::string> overrides;
  if (!a.scenario.empty()) overrides.push_back("scenario=" + a.scenario);
  if (!a.mount.empty()) overrides.push_back("mount=" + a.mount);
  if (a.seed) overrides.push_back(fmt::format("seed={}", *a.seed));
  overrides.insert(overrides.end(), a.overrides.begin(), a.overrides.end());
  return a.config_file.empty() ? Config::parse("{}", "<defaults>", overrides) : Config::load(a.config_file, overrides);
}

nlohmann::ordered_json summary_json(const simulation::SimulationConfig& c, const simulation::SimulationSummary& s) {
  nlohmann::ordered_json j;
  j["scenario"] = c.scenario;
  j["mount"] = c.mount.name;
  j["sensor_preset"] = c.sensor_preset;
  j["seed"] = c.seed;
  j["mode"] = c.mode == simulation::SimulationMode::kImages ? "images" : "features";
  j["duration_s"] = s.duration_s;
  j["path_length_m"] = s.path_length_m;
  j["walked_m"] = s.walked_m;
  j["imu"] = s.imu;
  j["frames"] = s.frames;
  j["gps"] = s.gps;
  j["mag"] = s.mag;
  j["groundtruth"] = s.groundtruth;
  if (c.mode == simulation::SimulationMode::kImages) {
    j["valid_depth_fraction"] = s.valid_depth_fraction;
    j["rendered_frames"] = s.rendered_frames;
  } else {
    j["landmarks"] = s.landmarks;
    j["observations"] = s.observations;
    j["depth_observation_fraction"] = s.depth_observation_fraction;
  }
  return j;
}

// --from-recording: the folder's real IMU and ground truth, its camera simulated in a world around
// the flight (the flight room unless --scenario names one).
void run_from_recording(const SimulateArgs& a, const Config& config) {
  const ConfigReads reads(config);
  namespace fs = std::filesystem;
  for (const auto& [flag, file] : {std::pair{"--imu-calibration", a.imu_calibration}, {"--camera-calibration", a.camera_calibration}})
    if (!file.empty() && !fs::is_regular_file(file)) throw UsageError(std::string(flag) + " " + file.string() + ": no such file");
  const fs::path mav0 = fs::is_directory(a.from_recording / "mav0") ? a.from_recording / "mav0" : a.from_recording;
  if (a.imu_calibration.empty() && fs::is_directory(mav0 / "imu0") && !fs::is_regular_file(mav0 / "imu0" / "sensor.yaml"))
    throw UsageError((mav0 / "imu0").string() +
                     " has no sensor.yaml (the IMU's noise model): pass --imu-calibration with the sensor.yaml of the same "
                     "IMU (for euroc-V1_02-imu, euroc-V1_01-micro's mav0/imu0/sensor.yaml)");
  const io::Recording source =
      io::read_euroc(a.from_recording, a.imu_calibration.empty() ? std::nullopt : std::optional(a.imu_calibration));
  if (source.groundtruth.size() < 2)
    throw UsageError(a.from_recording.string() + " has no ground truth (state_groundtruth_estimate0/data.csv) to fly along");
  const simulation::RecordedMotion motion(source.groundtruth);
  const simulation::Scenario scenario =
      config.has("scenario")
          ? simulation::make_scenario(simulation::read_scenario_name(config), simulation::read_scenario_options(config))
          : simulation::make_flight_room(motion.bounds(), static_cast<std::uint64_t>(get(config, flight_room_seed_key())));
  simulation::SimulationConfig sim = simulation::read_simulation_config(config, scenario);
  config.reject_unknown_keys(simulation::simulation_config_schema());
  sim.imu = *source.calibration.imu;  // the real IMU's own noise model
  if (!a.camera_calibration.empty()) {
    sim.camera = io::read_euroc_camera_yaml(a.camera_calibration, "cam0");
  } else if (!source.calibration.cameras.empty()) {
    sim.camera = source.calibration.cameras.front();  // the folder's own camera (no depth: VIO)
    sim.camera.name = "cam0";
  } else {
    spdlog::warn("{} has no camera calibration: simulating the {} camera at its {} mount (pass --camera-calibration "
                 "for the recording rig's own camera)",
                 a.from_recording.string(), sim.sensor_preset, sim.mount.name);
  }
  simulation::SimulateOptions options;
  options.threads = a.threads;
  options.overwrite = a.overwrite;
  spdlog::info("simulating the camera of {} in {}, seed {}", a.from_recording.string(), scenario.name, sim.seed);
  const auto summary = simulation::simulate_recorded_motion(scenario, sim, source, a.out, options);
  std::ofstream(a.out / "simulation.yaml") << config.dump(reads.defaults());
  auto json = summary_json(sim, summary);
  json["scenario"] = scenario.name;
  json["from_recording"] = std::filesystem::absolute(a.from_recording).string();
  std::ofstream(a.out / "summary.json") << json.dump(2) << "\n";
  std::cout << fmt::format(
      "wrote {}: the real IMU and ground truth of {} with a simulated {}x{} camera in {} ({}), {:.1f} s, {:.1f} m "
      "flown; {} imu, {} {}\n",
      a.out.string(), a.from_recording.string(), sim.camera.width, sim.camera.height, scenario.name,
      json["mode"].get<std::string>(), summary.duration_s, summary.walked_m, summary.imu, summary.frames,
      sim.mode == simulation::SimulationMode::kImages ? "frames" : "feature frames");
}

void run(const SimulateArgs& a) {
  if (a.list) return list_scenarios();
  if (a.out.empty()) throw UsageError("--out is required");
  if (a.from_recording.empty() && (!a.imu_calibration.empty() || !a.camera_calibration.empty()))
    throw UsageError("--imu-calibration and --camera-calibration go with --from-recording");
  if (!a.from_recording.empty()) {
    if (!a.mount.empty()) throw UsageError("--mount does not apply to --from-recording: the recording's motion is kept");
    return run_from_recording(a, build_config(a));
  }
  const Config config = build_config(a);
  const ConfigReads reads(config);
  const std::string name = simulation::read_scenario_name(config);
  const simulation::Scenario scenario = simulation::make_scenario(name, simulation::read_scenario_options(config));
  const simulation::SimulationConfig sim = simulation::read_simulation_config(config, scenario);
  config.reject_unknown_keys(simulation::simulation_config_schema());

  simulation::SimulateOptions options;
  if (!a.cache.empty()) options.cache_dir = a.cache;
  options.threads = a.threads;
  options.overwrite = a.overwrite;
  // The frame count is known once the walk is laid out: the bar starts with the first frame.
  std::unique_ptr<Progress> progress;
  const char* label = sim.mode == simulation::SimulationMode::kImages ? "rendering frames" : "observing features";
  options.on_frame = [&progress, label](std::size_t done, std::size_t total) {
    if (!progress) progress = std::make_unique<Progress>(label, total);
    progress->update(done);
  };
  spdlog::info("simulating {} with the {} mount, seed {}", name, sim.mount.name, sim.seed);
  const auto summary = simulation::simulate(scenario, sim, a.out, options);
  if (progress) progress->finish();

  std::ofstream(a.out / "simulation.yaml") << config.dump(reads.defaults());
  const auto json = summary_json(sim, summary);
  std::ofstream(a.out / "summary.json") << json.dump(2) << "\n";
  std::cout << fmt::format(
      "wrote {}: {} ({} mount, {}), {:.1f} s, {:.1f} m walked of a {:.1f} m path; {} imu, {} {}, {} gps, {} mag, "
      "{} ground-truth samples; frame stage {:.1f} s ({} rendered)\n",
      a.out.string(), name, sim.mount.name, json["mode"].get<std::string>(), summary.duration_s, summary.walked_m,
      summary.path_length_m, summary.imu, summary.frames,
      sim.mode == simulation::SimulationMode::kImages ? "frames" : "feature frames", summary.gps, summary.mag,
      summary.groundtruth, summary.frames_seconds, summary.rendered_frames);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("simulate", "Simulate a walk through a scenario and write a navaid recording with ground truth");
  auto a = std::make_shared<SimulateArgs>();
  cmd->add_option("--scenario", a->scenario, "Scenario name (see --list)");
  cmd->add_option("--mount", a->mount, "Sensor mount: head, cane or hand (default: the scenario's)");
  cmd->add_option("--seed", a->seed, "Noise seed (default 0); the rendering does not depend on it")->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", a->out, "Output folder for the recording");
  cmd->add_option("--config", a->config_file, "YAML configuration file (docs/simulate.md)")->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a configuration key, e.g. --set sensor.imu.rate=400 (repeatable)");
  cmd->add_option("--from-recording", a->from_recording,
                  "EuRoC/ASL folder: keep its real IMU and ground truth, simulate only its camera (docs/simulate.md)");
  cmd->add_option("--imu-calibration", a->imu_calibration,
                  "With --from-recording: an EuRoC imu sensor.yaml for a folder without one");
  cmd->add_option("--camera-calibration", a->camera_calibration,
                  "With --from-recording: an EuRoC camera sensor.yaml to simulate instead of the folder's cam0");
  cmd->add_option("--cache", a->cache, "Render cache folder: noise-free frames re-used across seeds");
  cmd->add_option("--threads", a->threads, "Frame workers (default: all cores); the output does not depend on it")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--overwrite", a->overwrite, "Replace the recording files in an existing output folder");
  cmd->add_flag("--list", a->list, "List the scenarios and exit");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
