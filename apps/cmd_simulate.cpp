// navaid simulate: walk a scenario with a mounted sensor rig and write a navaid recording with
// ground truth (docs/simulate.md).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <fstream>
#include <memory>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/simulation/simulator.hpp"
#include "navaid/experiments/progress.hpp"

namespace navaid::cli {

using experiments::Progress;


namespace {

struct SimulateArgs {
  std::string scenario, mount;
  std::optional<long long> seed;
  std::filesystem::path out, config_file, cache;
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

void run(const SimulateArgs& a) {
  if (a.list) return list_scenarios();
  if (a.out.empty()) throw UsageError("--out is required");
  const Config config = build_config(a);
  const std::string name = simulation::read_scenario_name(config);
  const simulation::Scenario scenario = simulation::make_scenario(name, simulation::read_scenario_options(config));
  const simulation::SimulationConfig sim = simulation::read_simulation_config(config, scenario);
  config.reject_unknown_keys();

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

  std::ofstream(a.out / "simulation.yaml") << config.dump();
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
  cmd->add_option("--cache", a->cache, "Render cache folder: noise-free frames re-used across seeds");
  cmd->add_option("--threads", a->threads, "Frame workers (default: all cores); the output does not depend on it")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--overwrite", a->overwrite, "Replace the recording files in an existing output folder");
  cmd->add_flag("--list", a->list, "List the scenarios and exit");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
