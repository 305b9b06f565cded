#include "navaid/experiments/trial_study.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <optional>
#include <chrono>
#include <exception>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/closed_loop_trial.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/experiments/reproduction_statistics.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Student-t interval of the mean; every measure of a trial is >= 0, so the interval is cut at 0
/// (a few trials with rare contacts would otherwise report negative counts).
nlohmann::ordered_json interval_json(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  MeanInterval m = mean_interval(v);
  if (std::isfinite(m.low)) m.low = std::max(0.0, m.low);
  const auto finite_or_null = [](double x) -> nlohmann::ordered_json { return std::isfinite(x) ? nlohmann::ordered_json(x) : nullptr; };
  return {{"mean", m.mean}, {"std", m.std}, {"ci95", {finite_or_null(m.low), finite_or_null(m.high)}}, {"n", m.n}};
}

std::string md_interval(const nlohmann::ordered_json& j, int digits) {
  if (j.is_null()) return "-";
  const auto& ci = j["ci95"];
  if (ci[0].is_null()) return fmt::format("{:.{}f}", j["mean"].get<double>(), digits);
  return fmt::format("{:.{}f} [{:.{}f}, {:.{}f}]", j["mean"].get<double>(), digits, ci[0].get<double>(), digits,
                     ci[1].get<double>(), digits);
}

}  // namespace

std::string replay_command(const TrialStudySpec& spec, std::uint64_t seed, const fs::path& out) {
  std::string cmd = fmt::format("navaid trial --scenario {} --device {} --user {} --seeds {}..{} --layouts {}",
                                shell_quote(spec.scenario), shell_quote(spec.device), shell_quote(spec.user), seed,
                                seed, spec.layouts);
  for (const auto& o : spec.overrides) cmd += " --set " + shell_quote(o);
  return cmd + " --keep all --out " + shell_quote(out.string());
}

nlohmann::ordered_json run_trial_study(const TrialStudySpec& spec, const fs::path& out, std::vector<TrialResult>* trials) {
  if (spec.scenario.empty()) throw UsageError("--scenario is required");
  if (out.empty()) throw UsageError("--out is required");
  if (spec.last_seed < spec.first_seed) throw UsageError("--seeds A..B needs A <= B");
  if (spec.jobs == 0) throw UsageError("--jobs must be at least 1");
  if (spec.layouts != "default" && spec.layouts != "random") throw UsageError("--layouts is default or random");
  if (spec.keep != "all" && spec.keep != "failures" && spec.keep != "none")
    throw UsageError("--keep is all, failures or none");
  // Configuration errors surface before any trial starts: the preset, the user, the keys.
  const fs::path preset = spec.device == "none" ? fs::path() : runtime::device_preset_file(spec.device);
  std::vector<std::string> overrides = spec.overrides;
  overrides.push_back("user.model=" + spec.user);
  if (spec.layouts == "random") overrides.push_back("simulation.layout=random");
  const Config base = preset.empty() ? Config::parse("{}", "<no device>", overrides) : Config::load(preset, overrides);

  fs::create_directories(out / "trials");
  const std::size_t n = spec.last_seed - spec.first_seed + 1;
  std::vector<std::optional<TrialResult>> results(n);
  std::atomic<std::size_t> next{0}, done{0};
  std::exception_ptr failure;
  std::mutex m;
  const auto t0 = std::chrono::steady_clock::now();
  const auto worker = [&] {
    for (;;) {
      const std::size_t i = next++;
      if (i >= n) return;
      {
        std::lock_guard<std::mutex> lock(m);
        if (failure) return;
      }
      const std::uint64_t seed = spec.first_seed + i;
      const fs::path dir = out / "trials" / fmt::format("seed-{}", seed);
      try {
        // Copying the configuration reads base's yaml-cpp nodes, which are not safe to read from two
        // threads at once (a crash one run in ~7, caught under gdb): one copy at a time.
        std::unique_lock<std::mutex> copying(m);
        TrialSpec t{spec.scenario, spec.layouts == "random" ? seed : 0, seed, base, true};
        copying.unlock();
        TrialResult r = run_trial(t, dir);
        const bool notable = !r.success || !r.contacts.empty() || !r.into_obstacle.empty();
        if (spec.keep == "none" || (spec.keep == "failures" && !notable)) fs::remove_all(dir);
        results[i] = std::move(r);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(m);
        if (!failure)
          failure = std::make_exception_ptr(Error(fmt::format("trial seed {} failed: {} (replay: {})", seed, e.what(),
                                                              replay_command(spec, seed, out / "replay"))));
        return;
      }
      const std::size_t k = ++done;
      if (!spec.quiet) {
        std::lock_guard<std::mutex> lock(m);
        std::cerr << fmt::format("\rtrials {}/{}", k, n) << (k == n ? "\n" : "") << std::flush;
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < std::min<std::size_t>(spec.jobs, n); ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::ofstream csv(out / "trials.csv");
  if (!csv) throw IoError((out / "trials.csv").string(), "cannot write");
  csv << "seed,world_seed,success,outcome,duration_s,path_length_m,mean_speed_mps,body_contacts,cane_contacts,"
         "head_contacts,torso_contacts,legs_contacts,into_obstacle,corrections,stops,cane_avoidances,experimenter_corrections,wall_s,replay\n";
  std::vector<double> duration, length, speed, body, cane, corrections, into, trial_wall, head, experimenter;
  std::size_t successes = 0;
  nlohmann::ordered_json into_list = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < n; ++i) {
    const TrialResult& r = *results[i];
    const std::uint64_t seed = spec.first_seed + i;
    std::size_t by_part[4] = {0, 0, 0, 0};
    for (const auto& c : r.contacts) ++by_part[static_cast<int>(c.part)];
    const std::string replay = replay_command(spec, seed, out / "replay" / fmt::format("seed-{}", seed));
    csv << fmt::format("{},{},{},{},{:.3f},{:.3f},{:.4f},{},{},{},{},{},{},{},{},{},{},{:.3f},\"{}\"\n", seed,
                       r.summary["world_seed"].get<std::uint64_t>(), r.success ? 1 : 0, r.outcome, r.duration_s,
                       r.path_length_m, r.mean_speed_mps, r.body_contacts, r.cane_contacts, by_part[2], by_part[1],
                       by_part[0], r.into_obstacle.size(), r.user.corrections, r.user.stops, r.user.cane_avoidances,
                       r.experimenter_corrections, r.wall_s, replay);
    successes += r.success ? 1 : 0;
    if (r.success) {
      duration.push_back(r.duration_s);
      speed.push_back(r.mean_speed_mps);
      length.push_back(r.path_length_m);
    }
    body.push_back(static_cast<double>(r.body_contacts));
    head.push_back(static_cast<double>(by_part[2]));
    cane.push_back(static_cast<double>(r.cane_contacts));
    corrections.push_back(static_cast<double>(r.user.corrections));
    experimenter.push_back(static_cast<double>(r.experimenter_corrections));
    into.push_back(static_cast<double>(r.into_obstacle.size()));
    trial_wall.push_back(r.wall_s);
    for (const auto& g : r.into_obstacle)
      into_list.push_back({{"seed", seed}, {"t_s", g.t_s}, {"instruction", g.instruction}, {"direction_deg", g.direction_deg},
                           {"obstacle", g.semantic}, {"replay", replay}});
  }
  const ProportionInterval success = wilson_interval(successes, n);
  nlohmann::ordered_json j;
  j["label"] = "simulated users (closed loop), not human results";
  j["scenario"] = spec.scenario;
  j["device"] = spec.device;
  j["user"] = spec.user;
  j["layouts"] = spec.layouts;
  j["seeds"] = {spec.first_seed, spec.last_seed};
  j["overrides"] = spec.overrides;
  j["trials"] = n;
  j["success"] = {{"count", successes}, {"rate", success.rate}, {"ci95", {success.low, success.high}}};
  j["body_contacts_per_trial"] = interval_json(body);
  j["head_contacts_per_trial"] = interval_json(head);
  j["cane_contacts_per_trial"] = interval_json(cane);
  j["corrections_per_trial"] = interval_json(corrections);
  j["experimenter_corrections_per_trial"] = interval_json(experimenter);
  j["guidance_into_obstacle_per_trial"] = interval_json(into);
  j["duration_s_successful"] = interval_json(duration);
  j["speed_mps_successful"] = interval_json(speed);
  j["path_length_m_successful"] = interval_json(length);
  j["guidance_into_obstacle"] = into_list;
  j["time"] = {{"wall_s", wall_s}, {"jobs", spec.jobs}, {"per_trial_wall_s", interval_json(trial_wall)}};
  std::ofstream(out / "summary.json") << j.dump(2) << "\n";

  std::ofstream md(out / "summary.md");
  md << fmt::format("# {} trials: {} with {}, user {} (simulated users, not human results)\n\n", n, spec.scenario,
                    spec.device, spec.user)
     << "| measure | mean [95 % CI] |\n|---|---|\n"
     << fmt::format("| success | {:.1f} % [{:.1f}, {:.1f}] ({} of {}) |\n", 100 * success.rate, 100 * success.low,
                    100 * success.high, successes, n)
     << fmt::format("| body contacts per trial | {} |\n", md_interval(j["body_contacts_per_trial"], 2))
     << fmt::format("| head contacts per trial | {} |\n", md_interval(j["head_contacts_per_trial"], 2))
     << fmt::format("| cane contacts per trial | {} |\n", md_interval(j["cane_contacts_per_trial"], 2))
     << fmt::format("| direction changes acted on per trial | {} |\n", md_interval(j["corrections_per_trial"], 2))
     << fmt::format("| experimenter's corrections per trial | {} |\n", md_interval(j["experimenter_corrections_per_trial"], 2))
     << fmt::format("| guidance into an obstacle per trial | {} |\n", md_interval(j["guidance_into_obstacle_per_trial"], 2))
     << fmt::format("| time to goal [s] (successful) | {} |\n", md_interval(j["duration_s_successful"], 1))
     << fmt::format("| walking speed [m/s] (successful) | {} |\n", md_interval(j["speed_mps_successful"], 2))
     << fmt::format("| path length [m] (successful) | {} |\n", md_interval(j["path_length_m_successful"], 1))
     << fmt::format("\n{} trials in {:.1f} s with {} jobs.\n", n, wall_s, spec.jobs);
  if (!into_list.empty()) {
    md << "\n## Guidance into an obstacle\n\n| seed | t [s] | instruction | obstacle | replay |\n|---|---|---|---|---|\n";
    for (const auto& g : into_list)
      md << fmt::format("| {} | {:.1f} | {} | {} | `{}` |\n", g["seed"].get<std::uint64_t>(), g["t_s"].get<double>(),
                        g["instruction"].get<std::string>(), g["obstacle"].get<std::string>(), g["replay"].get<std::string>());
  }
  if (trials) {
    trials->clear();
    for (auto& r : results) trials->push_back(std::move(*r));
  }
  return j;
}

}  // namespace navaid::experiments
