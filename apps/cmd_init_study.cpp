// navaid init-study: HPnP vs 3D-2D PnP initialization success rate and pose error over windows
// of feature-level recordings, per depth budget (estimation/initialization/pose_change_study.hpp,
// docs/initialization.md "HPnP vs PnP study"). Writes results.csv, summary.md, summary.json.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/estimation/initialization/pose_change_study.hpp"
#include "navaid/io/open_input.hpp"

namespace navaid::cli {
namespace fs = std::filesystem;
namespace est = navaid::estimation;
namespace {

struct InitStudyArgs {
  std::vector<fs::path> recordings;
  fs::path out;
  int gap = 10, stride = 0, windows = 0;
  std::uint64_t seed = 1;
  std::vector<std::string> budgets{"2", "3", "4", "5", "6", "8", "10", "all"};
  double threshold_px = 1.0, depth_threshold_px = 0.0, min_parallax_px = 20.0, min_baseline_m = 0.05;
  std::string camera;
  bool usac = false;
};

int parse_budget(const std::string& s) {
  if (s == "all") return est::kAllDepths;
  try {
    std::size_t used = 0;
    const int n = std::stoi(s, &used);
    if (used == s.size() && n >= 1) return n;
  } catch (const std::exception&) {
  }
  throw UsageError("--budgets: expected integers >= 1 or 'all', got '" + s + "'");
}

est::PoseChangeStudySequence load_sequence(const fs::path& path, const std::string& camera) {
  io::Recording rec = io::read_input(path);
  if (rec.features.empty()) throw IoError(path.string(), "has no feature observations (simulate with simulation.mode=features)");
  if (rec.groundtruth.empty()) throw IoError(path.string(), "has no ground truth");
  if (rec.calibration.cameras.empty()) throw IoError(path.string(), "has no camera calibration");
  est::PoseChangeStudySequence s;
  s.name = path.filename().empty() ? path.parent_path().filename().string() : path.filename().string();
  bool found = false;
  for (const auto& c : rec.calibration.cameras)
    if (camera.empty() ? !found : c.name == camera) {
      s.camera = c;
      found = true;
    }
  if (!found) throw UsageError(fmt::format("--camera: {} has no camera '{}'", path.string(), camera));
  for (auto& f : rec.features)
    if (f.camera == s.camera.name) s.frames.push_back(std::move(f));
  s.groundtruth = std::move(rec.groundtruth);
  return s;
}

nlohmann::ordered_json summary_json(const InitStudyArgs& a, const est::PoseChangeStudyOptions& o, std::size_t windows,
                                    const std::vector<est::PoseChangeStudySummary>& summary) {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  nlohmann::ordered_json j;
  j["recordings"] = nlohmann::ordered_json::array();
  for (const auto& r : a.recordings) j["recordings"].push_back(r.string());
  j["windows"] = windows;
  j["options"] = {{"gap", o.gap},
                  {"stride", o.stride},
                  {"min_parallax_px", o.min_parallax_px},
                  {"min_baseline_m", o.min_baseline_m},
                  {"ransac_threshold_px", o.pose_change.ransac_threshold_px},
                  {"depth_threshold_px", o.pose_change.depth_threshold_px > 0 ? o.pose_change.depth_threshold_px
                                                                               : o.pose_change.ransac_threshold_px},
                  {"essential", o.pose_change.essential_usac ? "usac_accurate" : "ransac"},
                  {"seed", o.seed}};
  j["success"] = {{"rotation_deg", o.success_rotation_deg},
                  {"translation_rel", o.success_translation_rel},
                  {"translation_abs_m", o.success_translation_abs_m}};
  j["summary"] = nlohmann::ordered_json::array();
  for (const auto& s : summary)
    j["summary"].push_back({{"N", est::budget_label(s.budget)},
                            {"method", est::to_string(s.method)},
                            {"windows", s.windows},
                            {"mean_depth_used", number(s.mean_depth_used)},
                            {"returned", s.returned},
                            {"successes", s.successes},
                            {"success_rate", number(s.success_rate)},
                            {"wilson95", {s.wilson_low, s.wilson_high}},
                            {"median_rot_err_deg", number(s.median_rot_err_deg)},
                            {"median_trans_err_m", number(s.median_trans_err_m)}});
  return j;
}

void run_init_study(const InitStudyArgs& a) {
  est::PoseChangeStudyOptions o;
  o.gap = a.gap;
  o.stride = a.stride > 0 ? a.stride : a.gap;
  o.seed = a.seed;
  o.min_parallax_px = a.min_parallax_px;
  o.min_baseline_m = a.min_baseline_m;
  o.pose_change.ransac_threshold_px = a.threshold_px;
  o.pose_change.depth_threshold_px = a.depth_threshold_px;
  o.pose_change.essential_usac = a.usac;
  o.depth_budgets.clear();
  for (const auto& b : a.budgets) o.depth_budgets.push_back(parse_budget(b));
  est::validate(o, "init-study");

  std::vector<est::PoseChangeWindow> candidates;
  for (const auto& path : a.recordings) {
    const auto seq = load_sequence(path, a.camera);
    auto w = est::make_pose_change_windows(seq, o);
    spdlog::info("{}: {} feature frames, {} candidate windows", path.string(), seq.frames.size(), w.size());
    candidates.insert(candidates.end(), std::make_move_iterator(w.begin()), std::make_move_iterator(w.end()));
  }
  const auto windows = est::select_windows(std::move(candidates), a.windows);
  if (windows.empty()) throw Error("init-study: no window with enough parallax and motion in the recordings");

  std::vector<est::PoseChangeStudyRow> rows;
  for (const auto& w : windows) {
    auto r = est::evaluate_pose_change_window(w, o);
    rows.insert(rows.end(), r.begin(), r.end());
    if ((w.index + 1) % 50 == 0) spdlog::info("{} / {} windows", w.index + 1, windows.size());
  }
  const auto summary = est::summarize_pose_change_study(rows, o);

  fs::create_directories(a.out);
  const fs::path csv = a.out / "results.csv", md = a.out / "summary.md", json = a.out / "summary.json";
  {
    std::ofstream out(csv);
    est::write_pose_change_rows_csv(out, rows);
    if (!out) throw IoError(csv.string(), "cannot write");
  }
  const std::string table = est::pose_change_summary_markdown(summary);
  std::vector<std::string> names;
  for (const auto& r : a.recordings) names.push_back(r.string());
  {
    std::ofstream out(md);
    out << fmt::format(
        "# HPnP vs 3D-2D PnP: initialization success per depth budget\n\n{} windows (frame pairs i, i+{}) from {}; "
        "success = pose returned with rotation error < {} deg and translation error < {} x baseline + {} m. "
        "Median errors over returned poses. Thresholds: 2D {} px, depth reprojection {} px; HPnP essential "
        "matrix by {}; seed {}.\n\n",
        windows.size(), o.gap, fmt::join(names, ", "), o.success_rotation_deg, o.success_translation_rel,
        o.success_translation_abs_m, o.pose_change.ransac_threshold_px,
        o.pose_change.depth_threshold_px > 0 ? o.pose_change.depth_threshold_px : o.pose_change.ransac_threshold_px,
        o.pose_change.essential_usac ? "USAC_ACCURATE" : "RANSAC", o.seed);
    out << table;
    if (!out) throw IoError(md.string(), "cannot write");
  }
  {
    std::ofstream out(json);
    out << summary_json(a, o, windows.size(), summary).dump(2) << "\n";
    if (!out) throw IoError(json.string(), "cannot write");
  }
  std::cout << fmt::format("{} windows\n", windows.size()) << table
            << fmt::format("wrote {}, {}, {}\n", csv.string(), md.string(), json.string());
}

}  // namespace

void add_init_study_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("init-study", "HPnP vs 3D-2D PnP pose-change success rate per depth budget");
  auto a = std::make_shared<InitStudyArgs>();
  cmd->add_option("--recording", a->recordings, "Feature-level recording with ground truth (repeatable)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", a->out, "Folder for results.csv, summary.md, summary.json")->required();
  cmd->add_option("--gap", a->gap, "Frames between the two frames of a window")->capture_default_str();
  cmd->add_option("--stride", a->stride, "Frames between window starts (0: the gap)")->capture_default_str();
  cmd->add_option("--windows", a->windows, "Use at most N windows, evenly spaced (0: all)")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the depth subsets and RANSAC")->capture_default_str();
  cmd->add_option("--budgets", a->budgets, "Depth budgets N (integers or 'all')")->delimiter(',')->capture_default_str();
  cmd->add_option("--threshold-px", a->threshold_px, "2D-2D inlier threshold [px]")->capture_default_str();
  cmd->add_option("--depth-threshold-px", a->depth_threshold_px,
                  "Reprojection threshold of depth features [px] (0: --threshold-px)")
      ->capture_default_str();
  cmd->add_option("--min-parallax-px", a->min_parallax_px, "Mean feature displacement a window needs [px]")
      ->capture_default_str();
  cmd->add_option("--min-baseline", a->min_baseline_m, "True baseline a window needs [m]")->capture_default_str();
  cmd->add_option("--camera", a->camera, "Camera name (default: the first)");
  cmd->add_flag("--usac", a->usac, "HPnP's essential matrix by OpenCV USAC_ACCURATE instead of RANSAC");
  cmd->callback([a] { run_init_study(*a); });
}

}  // namespace navaid::cli
