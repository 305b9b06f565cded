// navaid consistency: Monte-Carlo NEES of N runs of one recording with different noise seeds
// (evaluation/monte_carlo_nees.hpp): per-epoch ANEES of position and orientation with the
// chi-square bounds, the time average with its bounds; consistency.csv / .json / .md and a figure
// drawn by experiments/figures/plot_consistency.py. Definitions in docs/evaluation.md.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/evaluation/monte_carlo_nees.hpp"
#include "navaid/experiments/run_folder.hpp"
#include "navaid/io/open_input.hpp"
#include "navaid/experiments/figure_script.hpp"

namespace navaid::cli {

using experiments::run_figure_script;

namespace fs = std::filesystem;
namespace ex = navaid::experiments;
namespace ev = navaid::evaluation;
namespace {

struct ConsistencyArgs {
  std::vector<fs::path> runs;
  fs::path out;
  double confidence = 0.95;
  double skip_s = 0.0;
  bool no_plot = false;
};

std::vector<io::StampedPose> recording_groundtruth(const fs::path& recording) {
  if (!fs::exists(recording))
    throw IoError(recording.string(), "does not exist (the recording named in a run's summary.json)");
  const io::Recording r = io::read_input(recording);
  if (r.groundtruth.empty()) throw IoError(recording.string(), "has no ground truth to compute the NEES against");
  std::vector<io::StampedPose> poses;
  poses.reserve(r.groundtruth.size());
  for (const auto& g : r.groundtruth) poses.push_back({g.t, g.T_W_B});
  return poses;
}

nlohmann::ordered_json bounds_json(const ev::NeesBounds& b) {
  return {{"dof", b.dof}, {"lower", b.lower}, {"upper", b.upper}};
}

nlohmann::ordered_json statistics_json(const ev::AneesStatistics& s) {
  return {{"dof", s.dof},
          {"epoch_bounds", bounds_json(s.epoch_bounds)},
          {"fraction_of_epochs_inside", s.fraction_inside},
          {"epochs_below", s.epochs_below},
          {"epochs_above", s.epochs_above},
          {"time_average", s.time_average},
          {"time_average_bounds",
           {{"conservative", bounds_json(s.conservative_bounds)},
            {"independent_epochs", bounds_json(s.independent_bounds)},
            {"effective", bounds_json(s.effective_bounds)}}},
          {"effective_epochs_per_run", s.effective_epochs},
          {"consistent", s.consistent()},
          {"run_averages", s.run_averages}};
}

std::string markdown(const ConsistencyArgs& a, const ev::MonteCarloNees& m) {
  const int pct = static_cast<int>(std::lround(100 * a.confidence));
  std::string md = fmt::format(
      "# Monte-Carlo NEES consistency\n\n{} runs, {} shared epochs ({} to {} s, the first {} s of the shared span "
      "skipped), {} % two-sided chi-square bounds.\n\n"
      "| | ANEES_k bounds chi2(N d)/N | epochs inside | time average | conservative bounds chi2(N d)/N | "
      "independent-epoch bounds chi2(N K d)/(N K) | K_eff | K_eff bounds | verdict |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      m.runs.size(), m.t.size(), format_seconds(m.t.front()), format_seconds(m.t.back()), a.skip_s, pct);
  for (const auto& [name, s] : {std::pair{"position", &m.position}, std::pair{"orientation", &m.orientation}})
    md += fmt::format(
        "| {} | [{:.3f}, {:.3f}] | {:.1f} % ({} below, {} above) | {:.3f} | [{:.3f}, {:.3f}] | [{:.4f}, {:.4f}] | "
        "{:.1f} | [{:.3f}, {:.3f}] | {} |\n",
        name, s->epoch_bounds.lower, s->epoch_bounds.upper, 100 * s->fraction_inside, s->epochs_below, s->epochs_above,
        s->time_average, s->conservative_bounds.lower, s->conservative_bounds.upper, s->independent_bounds.lower,
        s->independent_bounds.upper, s->effective_epochs, s->effective_bounds.lower, s->effective_bounds.upper,
        s->consistent() ? "consistent" : "inconsistent");
  md +=
      "\nThe epochs of one run are correlated, so the independent-epoch bounds are far too narrow; the verdict uses "
      "the conservative bounds (each run's time average counted as one sample). K_eff, the effective number of "
      "independent epochs per run, is matched to the spread of the per-run averages (docs/evaluation.md).\n\n"
      "| run | epochs dropped | mean NEES position | mean NEES orientation |\n|---|---|---|---|\n";
  for (std::size_t i = 0; i < m.runs.size(); ++i)
    md += fmt::format("| {} | {} | {:.3f} | {:.3f} |\n", fs::path(m.runs[i]).filename().string(), m.dropped[i], m.position.run_averages[i],
                      m.orientation.run_averages[i]);
  return md;
}

void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  if (!out) throw IoError(file.string(), "cannot write");
}

void run_consistency(const ConsistencyArgs& a) {
  if (!(a.confidence > 0.0 && a.confidence < 1.0))
    throw UsageError(fmt::format("--confidence must be in (0, 1), got {}", a.confidence));
  if (!(a.skip_s >= 0.0) || !std::isfinite(a.skip_s))
    throw UsageError(fmt::format("--skip must be a non-negative number of seconds, got {}", a.skip_s));
  // A shell glob such as .../rgbd-vio/seed* also matches the seed<k>.log files navaid ablate writes
  // beside the run folders: files are not runs, and are skipped.
  std::vector<fs::path> runs;
  std::size_t skipped_files = 0;
  for (const fs::path& p : a.runs) {
    if (fs::is_directory(p))
      runs.push_back(p);
    else
      ++skipped_files;
  }
  if (skipped_files > 0) spdlog::info("--runs: skipped {} arguments that are files, not run folders", skipped_files);
  if (runs.size() < 2) throw UsageError(fmt::format("--runs needs at least 2 run folders, got {}", runs.size()));
  // Runs of one simulated recording usually share its ground truth: read each recording once.
  std::map<fs::path, std::vector<io::StampedPose>> groundtruth;
  std::vector<ev::NeesSeries> series;
  for (const fs::path& run : runs) {
    const fs::path recording = ex::run_recording(run);
    auto it = groundtruth.find(recording);
    if (it == groundtruth.end()) it = groundtruth.emplace(recording, recording_groundtruth(recording)).first;
    series.push_back(ev::first_state_nees_series(run.string(), ex::read_estimates_csv(run / "estimates.csv"), it->second));
    spdlog::info("{}: {} epochs", run.string(), series.back().t.size());
  }
  const ev::MonteCarloNees m = ev::monte_carlo_nees(series, a.confidence, seconds_to_ns(a.skip_s));

  fs::create_directories(a.out);
  const fs::path csv_file = a.out / "consistency.csv", json_file = a.out / "consistency.json",
                 md_file = a.out / "consistency.md", png_file = a.out / "consistency.png";
  std::string csv = "epoch,t,anees_pos,anees_rot,runs\n";
  for (std::size_t k = 0; k < m.t.size(); ++k)
    csv += fmt::format("{},{},{},{},{}\n", k, format_seconds(m.t[k]), m.position.anees[k], m.orientation.anees[k],
                       m.runs.size());
  write_file(csv_file, csv);
  nlohmann::ordered_json j;
  j["confidence"] = a.confidence;
  j["runs"] = m.runs;
  j["epochs_dropped"] = m.dropped;
  j["skip_s"] = a.skip_s;
  j["epochs"] = m.t.size();
  j["first_epoch_s"] = format_seconds(m.t.front());
  j["last_epoch_s"] = format_seconds(m.t.back());
  j["nees_frame"] = "first state (4-DOF: yaw + translation at each run's first estimate), as navaid run";
  j["position"] = statistics_json(m.position);
  j["orientation"] = statistics_json(m.orientation);
  write_file(json_file, j.dump(2) + "\n");
  write_file(md_file, markdown(a, m));

  for (const auto& [name, s] : {std::pair{"position", &m.position}, std::pair{"orientation", &m.orientation}})
    std::cout << fmt::format(
        "{}: ANEES {:.3f} over {} runs x {} epochs, bounds [{:.3f}, {:.3f}] ({}); {:.1f} % of epochs inside\n", name,
        s->time_average, s->runs, s->epochs, s->conservative_bounds.lower, s->conservative_bounds.upper,
        s->consistent() ? "consistent" : "inconsistent", 100 * s->fraction_inside);
  std::cout << "wrote " << csv_file.string() << ", " << json_file.string() << ", " << md_file.string();
  if (!a.no_plot) {
    run_figure_script("plot_consistency.py", {csv_file.string(), json_file.string(), "--out", png_file.string()});
    std::cout << ", " << png_file.string();
  }
  std::cout << "\n";
}

}  // namespace

void add_consistency_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("consistency",
                                 "Monte-Carlo NEES (per-epoch ANEES) of runs of one recording with different seeds");
  auto a = std::make_shared<ConsistencyArgs>();
  cmd->add_option("--runs", a->runs,
                  "Run folders of navaid run (estimates.csv, summary.json), e.g. .../seed* (files are skipped)")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--out", a->out, "Folder for consistency.csv, .json, .md and .png")->required();
  cmd->add_option("--confidence", a->confidence, "Two-sided confidence of the chi-square bounds")->capture_default_str();
  cmd->add_option("--skip", a->skip_s, "Seconds left out at the start of the shared epochs (start-up transient)")
      ->capture_default_str();
  cmd->add_flag("--no-plot", a->no_plot, "Do not draw consistency.png");
  cmd->callback([a] { run_consistency(*a); });
}

}  // namespace navaid::cli
