// navaid rumble: the BYU augmented cane's cost function (FICF or CACF) and rumble table on every
// scan of a `navaid map` obstacle_scan.csv; writes rumble.csv (t_ns, C_F, C_L, C_R, state),
// guidance_timeline.csv (the input of `navaid cues`) and summary.json, and prints the count per state and the number of state changes.
#include <fmt/format.h>

#include <array>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/core/time.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/planning/byu_cost_functions.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/obstacle_scan_csv.hpp"

namespace navaid::cli {

namespace {

struct RumbleArgs {
  std::filesystem::path scans;
  std::string function;
  std::filesystem::path out;
  std::filesystem::path config_file;
  std::vector<std::string> overrides;
};

constexpr std::array<planning::RumbleState, 4> kStates = {planning::RumbleState::kOff, planning::RumbleState::kLeft,
                                                          planning::RumbleState::kRight, planning::RumbleState::kBoth};

void run(const RumbleArgs& a) {
  const std::optional<planning::ByuCostFunction> function = planning::byu_cost_function_from_string(a.function);
  if (!function) throw UsageError(fmt::format("--function must be ficf or cacf, not '{}'", a.function));
  const Config config = a.config_file.empty() ? Config::parse("{}", "<defaults>", a.overrides)
                                              : Config::load(a.config_file, a.overrides);
  const ConfigReads reads(config);
  const planning::ByuCostConfig byu = planning::read_byu_cost_config(config);
  config.reject_unknown_keys(planning::byu_cost_config_schema());
  const std::vector<mapping::ObstacleScan> scans = planning::read_obstacle_scan_csv(a.scans);
  const planning::ByuThresholds& thresholds = planning::byu_thresholds(*function, byu);

  std::filesystem::create_directories(a.out);
  const std::filesystem::path csv_path = a.out / "rumble.csv";
  std::ofstream csv(csv_path);
  if (!csv) throw IoError(csv_path.string(), "cannot write");
  csv << "t_ns,C_F,C_L,C_R,state\n";
  std::array<std::size_t, 4> count{};
  std::array<double, 4> seconds{};  // a state holds until the next scan
  std::size_t changes = 0;
  std::optional<planning::RumbleState> previous;
  std::vector<interaction::GuidanceTimelineEntry> timeline;  // one command per scan, for navaid cues
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const planning::ByuCosts c = planning::byu_costs(scans[i], *function, byu);
    const planning::RumbleState state = planning::rumble_state(c, thresholds);
    csv << fmt::format("{},{:.6g},{:.6g},{:.6g},{}\n", scans[i].t, c.forward, c.left, c.right,
                       planning::to_string(state));
    const auto k = static_cast<std::size_t>(state);
    ++count[k];
    if (i + 1 < scans.size()) seconds[k] += ns_to_seconds(scans[i + 1].t - scans[i].t);
    if (previous && *previous != state) ++changes;
    timeline.emplace_back(planning::rumble_command(scans[i].t, state));
    previous = state;
  }
  csv.close();
  if (!csv) throw IoError(csv_path.string(), "write failed");
  interaction::write_guidance_timeline_csv(a.out / "guidance_timeline.csv", timeline);

  nlohmann::ordered_json states = nlohmann::ordered_json::object();
  for (const planning::RumbleState s : kStates) {
    const auto k = static_cast<std::size_t>(s);
    states[std::string(planning::to_string(s))] = {{"scans", count[k]}, {"seconds", seconds[k]}};
  }
  nlohmann::ordered_json summary = {
      {"scans_file", a.scans.string()},
      {"function", std::string(planning::to_string(*function))},
      {"forward_threshold", thresholds.forward},
      {"left_right_threshold", thresholds.left_right},
      {"scans", scans.size()},
      {"states", states},
      {"state_changes", changes},
      {"duration_s", scans.size() > 1 ? ns_to_seconds(scans.back().t - scans.front().t) : 0.0},
  };
  std::ofstream(a.out / "summary.json") << summary.dump(2) << "\n";
  std::ofstream(a.out / "config.yaml") << config.dump(reads.defaults());

  std::cout << fmt::format("{}: {} scans, thresholds forward {} / left-right {}\n", planning::to_string(*function),
                           scans.size(), thresholds.forward, thresholds.left_right);
  for (const planning::RumbleState s : kStates) {
    const auto k = static_cast<std::size_t>(s);
    std::cout << fmt::format("  {:<5} {:6} scans {:8.2f} s\n", planning::to_string(s), count[k], seconds[k]);
  }
  std::cout << fmt::format("state changes (rumble signals): {}\n", changes);
  std::cout << fmt::format("wrote {}, {}\n", csv_path.string(), (a.out / "summary.json").string());
}

}  // namespace

void add_rumble_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "rumble", "BYU augmented cane: FICF / CACF cost and rumble state per scan of a navaid map obstacle_scan.csv");
  auto a = std::make_shared<RumbleArgs>();
  cmd->add_option("--scans", a->scans, "obstacle_scan.csv written by navaid map --set mapping.obstacles.enabled=true")
      ->required();
  cmd->add_option("--function", a->function, "ficf | cacf")->required();
  cmd->add_option("--out", a->out, "Output folder (rumble.csv, guidance_timeline.csv, summary.json, config.yaml)")->required();
  cmd->add_option("--config", a->config_file, "YAML configuration (planning.byu.* keys, docs/planning.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set planning.byu.cacf.forward_threshold=4 (repeatable)");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
