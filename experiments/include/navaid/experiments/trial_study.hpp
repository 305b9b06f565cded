#pragma once
// Many closed-loop trials of one condition (scenario x device x user), one per seed, on several
// threads, gathered into one table with confidence intervals (docs/simulated-users.md): `navaid
// trial`. Every row carries the command that replays its trial bit for bit.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navaid/experiments/closed_loop_trial.hpp"

namespace navaid::experiments {

struct TrialStudySpec {
  std::string scenario;
  std::string device = "none";  ///< a preset of runtime/devices, or none (the cane alone)
  std::string user = "typical"; ///< a user model (simulated_user.hpp)
  std::uint64_t first_seed = 1, last_seed = 1;
  /// The layout of each trial's world: "default" (the scenario's documented seed) or "random"
  /// (the trial's seed: obstacles moved within the scenario family's rules).
  std::string layouts = "default";
  std::vector<std::string> overrides;  ///< --set KEY=VALUE
  unsigned jobs = 1;                   ///< trials at once
  /// Trial folders kept: "all", "failures" (unsuccessful, with a contact, or with guidance into an
  /// obstacle) or "none" (trials.csv and summary.json only).
  std::string keep = "failures";
  bool quiet = false;                  ///< no progress line
};

/// Runs the trials and writes out/trials.csv, out/summary.json, out/summary.md and out/trials/
/// seed-N/ folders as `keep` says; returns the summary. UsageError on a bad spec (names the option);
/// a trial's error stops the study with the seed named. `trials`, when given, receives every
/// trial's result in seed order.
nlohmann::ordered_json run_trial_study(const TrialStudySpec& spec, const std::filesystem::path& out,
                                       std::vector<TrialResult>* trials = nullptr);

/// The `navaid trial` command that replays seed `seed` of the study into `out`.
std::string replay_command(const TrialStudySpec& spec, std::uint64_t seed, const std::filesystem::path& out);

}  // namespace navaid::experiments
