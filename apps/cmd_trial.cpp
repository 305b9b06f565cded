// navaid trial: the command line of experiments::run_trial_study (trial_study.hpp): closed-loop
// trials of a simulated user with a device (docs/simulated-users.md).
#include <charconv>
#include <fstream>
#include <tuple>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/trial_study.hpp"

namespace navaid::cli {

namespace {

/// "A..B" or "A" as an inclusive range of seeds.
std::pair<std::uint64_t, std::uint64_t> parse_seeds(const std::string& text) {
  const auto dots = text.find("..");
  const std::string a = text.substr(0, dots), b = dots == std::string::npos ? a : text.substr(dots + 2);
  std::pair<std::uint64_t, std::uint64_t> r{0, 0};
  const auto parse = [&text](const std::string& s, std::uint64_t& v) {
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || p != s.data() + s.size())
      throw UsageError("--seeds takes A..B or A with whole numbers, not '" + text + "'");
  };
  parse(a, r.first);
  parse(b, r.second);
  if (r.second < r.first) throw UsageError("--seeds A..B needs A <= B, not '" + text + "'");
  return r;
}

}  // namespace

void add_trial_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("trial", "Closed-loop trials: a simulated user walks a scenario guided by a device "
                                          "(docs/simulated-users.md)");
  auto spec = std::make_shared<experiments::TrialStudySpec>();
  auto seeds = std::make_shared<std::string>("1");
  auto out = std::make_shared<std::filesystem::path>();
  cmd->add_option("--scenario", spec->scenario, "A walk scenario, e.g. corridor, obstacle-course")->required();
  cmd->add_option("--device", spec->device,
                  "A device preset (smart-cane, augmented-cane) or none: the long cane alone")
      ->capture_default_str();
  cmd->add_option("--user", spec->user, "User model: typical, cautious, hasty, sighted-blindfolded")->capture_default_str();
  cmd->add_option("--seeds", *seeds, "Trial seeds A..B (one trial each)")->capture_default_str();
  cmd->add_option("--layouts", spec->layouts, "default (the scenario's layout) or random (a layout per seed)")
      ->capture_default_str();
  cmd->add_option("--jobs", spec->jobs, "Trials at once")->capture_default_str();
  cmd->add_option("--keep", spec->keep, "Trial folders kept: all, failures (failed, contact or guidance into an "
                                        "obstacle) or none")
      ->capture_default_str();
  cmd->add_option("--set", spec->overrides, "Override a key (user.*, trial.*, device.*, estimator.*, ...), repeatable");
  cmd->add_flag("--quiet", spec->quiet, "No progress line");
  cmd->add_option("--out", *out, "Study folder (trials.csv, summary.json, summary.md, trials/seed-N/)")->required();
  cmd->callback([spec, seeds, out] {
    std::tie(spec->first_seed, spec->last_seed) = parse_seeds(*seeds);
    experiments::run_trial_study(*spec, *out);
    std::cout << std::ifstream(*out / "summary.md").rdbuf();
  });
}

}  // namespace navaid::cli
