// navaid eval: ATE (after 4-DOF / SE(3) / Sim(3) / no alignment) and RPE of an estimated TUM
// trajectory against ground truth; eval.json, per-pose errors and a figure drawn by
// experiments/figures/plot_eval.py. Definitions in docs/evaluation.md.
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/evaluation/trajectory_evaluation.hpp"
#include "navaid/io/open_input.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "navaid/experiments/figure_script.hpp"

namespace navaid::cli {

using experiments::run_figure_script;

namespace fs = std::filesystem;
namespace ex = navaid::experiments;
namespace ev = navaid::evaluation;
namespace {

struct EvalArgs {
  fs::path est, gt, out;
  std::string align = "4dof";
  std::size_t align_frames = 0;
  double tolerance_s = 0.02;
  std::vector<double> rpe_lengths;
  std::vector<double> rpe_percent{10, 20, 30, 40, 50};
  bool no_plot = false;
  // evo's conventions (docs/evaluation.md, "evo").
  bool align_given = false, evo_align = false, correct_scale = false;
  double t_max_diff_s = 0.0;  // 0 = rpg's association with --tolerance
  double delta = 0.0;         // 0 = no evo RPE
  std::string delta_unit = "f";
  bool all_pairs = false, pairs_from_reference = false;
  double delta_tol = 0.1;
};

// -a / bare --align is SE(3); -s alone corrects the scale only; with an alignment it makes Sim(3).
std::string resolved_alignment(const EvalArgs& a) {
  std::string align = a.evo_align ? "se3" : a.align;
  if (a.evo_align && a.align_given && a.align != "se3")
    throw UsageError("-a is --align se3; it cannot be combined with --align " + a.align);
  if (!a.correct_scale) return align;
  if (!a.evo_align && !a.align_given) return "scale";
  if (align == "se3" || align == "sim3") return "sim3";
  throw UsageError("--correct_scale makes an SE(3) alignment Sim(3), or alone corrects the scale; it cannot be "
                   "combined with --align " + align);
}

// A TUM file is read as a trajectory; a folder (navaid recording, EuRoC, TUM RGB-D) for its ground truth.
std::vector<io::StampedPose> read_groundtruth(const fs::path& path) {
  if (!fs::is_directory(path)) return io::read_tum_trajectory(path);
  const io::Recording recording = io::read_input(path);
  if (recording.groundtruth.empty()) throw IoError(path.string(), "has no ground truth to evaluate against");
  std::vector<io::StampedPose> poses;
  poses.reserve(recording.groundtruth.size());
  for (const auto& g : recording.groundtruth) poses.push_back({g.t, g.T_W_B});
  return poses;
}

nlohmann::ordered_json stats_json(const ev::ErrorStatistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std}, {"min", s.min}, {"max", s.max},
          {"count", s.count}};
}

nlohmann::ordered_json evaluation_json(const EvalArgs& a, const ev::TrajectoryEvaluation& e) {
  nlohmann::ordered_json j;
  j["estimate"] = a.est.string();
  j["groundtruth"] = a.gt.string();
  j["association"] = {{"rule", e.association},
                      {"tolerance_s", e.association == "evo" ? a.t_max_diff_s : a.tolerance_s},
                      {"estimate_poses", e.est_poses},
                      {"groundtruth_poses", e.gt_poses},
                      {"matched", e.pairs.size()}};
  const auto& T = e.ate.transform;
  nlohmann::ordered_json rotation = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r) rotation.push_back({T.R(r, 0), T.R(r, 1), T.R(r, 2)});
  j["alignment"] = {{"mode", std::string(ev::to_string(e.ate.alignment))},
                    {"frames", e.ate.align_frames},
                    {"scale", T.scale},
                    {"rotation", rotation},  // gt ~ scale * rotation * est + translation
                    {"translation", {T.t.x(), T.t.y(), T.t.z()}}};
  j["groundtruth_path_length_m"] = e.gt_path_length_m;
  j["ate"] = {{"position_m", stats_json(e.ate.position)}, {"rotation_deg", stats_json(e.ate.rotation_deg)}};
  j["rpe"] = nlohmann::ordered_json::array();
  for (const auto& r : e.rpe) {
    nlohmann::ordered_json x{{"length_m", r.length_m}, {"pairs", r.translation_errors.size()}};
    if (!r.empty()) {
      x["translation_m"] = stats_json(r.translation);
      x["translation_percent"] = stats_json(r.translation_percent);
      x["rotation_deg"] = stats_json(r.rotation_deg);
    }
    j["rpe"].push_back(x);
  }
  if (e.evo_rpe) {
    const auto& r = *e.evo_rpe;
    j["rpe_evo"] = {{"delta", r.options.delta},
                    {"delta_unit", std::string(ev::to_string(r.options.unit))},
                    {"all_pairs", r.options.all_pairs},
                    {"pairs_from_reference", r.options.pairs_from_reference},
                    {"rel_delta_tol", r.options.rel_delta_tol},
                    {"pairs", r.pairs.size()},
                    {"translation_m", stats_json(r.translation)},
                    {"rotation_deg", stats_json(r.rotation_deg)}};
  }
  return j;
}

void write_per_pose(const fs::path& file, const ev::TrajectoryEvaluation& e) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write");
  out << "t,gt_x,gt_y,gt_z,est_x,est_y,est_z,position_error_m,rotation_error_deg\n";
  for (std::size_t i = 0; i < e.pairs.size(); ++i) {
    const Vec3& g = e.pairs[i].gt.t;
    const Vec3& s = e.ate.aligned[i].t;
    out << fmt::format("{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.5f}\n", format_seconds(e.pairs[i].t_est),
                       g.x(), g.y(), g.z(), s.x(), s.y(), s.z(), e.ate.position_errors[i],
                       e.ate.rotation_errors_rad[i] * 180.0 / M_PI);
  }
  if (!out) throw IoError(file.string(), "write failed");
}

void run_eval(const EvalArgs& a) {
  ev::EvaluationOptions options;
  options.ate.alignment = *ev::alignment_mode_from_string(resolved_alignment(a));  // CLI11 has checked the name
  options.ate.align_frames = a.align_frames;
  if (!(a.tolerance_s > 0.0) || !std::isfinite(a.tolerance_s))
    throw UsageError(fmt::format("--tolerance must be a positive number of seconds, got {}", a.tolerance_s));
  options.tolerance = seconds_to_ns(a.tolerance_s);
  options.rpe_lengths_m = a.rpe_lengths;
  options.rpe_length_percent = a.rpe_percent;
  if (a.t_max_diff_s != 0.0) {
    if (!(a.t_max_diff_s > 0.0) || !std::isfinite(a.t_max_diff_s))
      throw UsageError(fmt::format("--t_max_diff must be a positive number of seconds, got {}", a.t_max_diff_s));
    options.evo_max_diff = seconds_to_ns(a.t_max_diff_s);
  }
  if (a.delta != 0.0) {
    ev::EvoRpeOptions rpe;
    rpe.delta = a.delta;
    rpe.unit = *ev::rpe_delta_unit_from_string(a.delta_unit);  // CLI11 has checked the letter
    rpe.all_pairs = a.all_pairs;
    rpe.pairs_from_reference = a.pairs_from_reference;
    rpe.rel_delta_tol = a.delta_tol;
    options.evo_rpe = rpe;
  } else if (a.all_pairs || a.pairs_from_reference) {
    throw UsageError("--all_pairs and --pairs_from_reference go with --delta (evo's RPE)");
  }

  const auto est = io::read_tum_trajectory(a.est);
  const auto gt = read_groundtruth(a.gt);
  const ev::TrajectoryEvaluation e = ev::evaluate_trajectory(est, gt, options);

  std::cout << fmt::format("matched poses: {} of {} estimated ({} ground-truth poses, {} association, tolerance {} s)\n",
                           e.pairs.size(), e.est_poses, e.gt_poses, e.association,
                           options.evo_max_diff ? a.t_max_diff_s : a.tolerance_s);
  std::cout << fmt::format("alignment: {} on {} poses, scale {:.6f}\n", ev::to_string(e.ate.alignment),
                           e.ate.align_frames, e.ate.transform.scale);
  std::cout << fmt::format("ATE RMSE: {:.6f} m (mean {:.4f}, median {:.4f}, max {:.4f} m; rotation RMSE {:.3f} deg)\n",
                           e.ate.position.rmse, e.ate.position.mean, e.ate.position.median, e.ate.position.max,
                           e.ate.rotation_deg.rmse);
  for (const auto& r : e.rpe) {
    if (r.empty())
      std::cout << fmt::format("RPE {:.2f} m: no sub-trajectory of that length\n", r.length_m);
    else
      std::cout << fmt::format("RPE {:.2f} m: translation mean {:.4f} m ({:.2f} %), rotation mean {:.3f} deg, {} pairs\n",
                               r.length_m, r.translation.mean, r.translation_percent.mean, r.rotation_deg.mean,
                               r.translation_errors.size());
  }
  if (e.evo_rpe) {
    const auto& r = *e.evo_rpe;
    std::cout << fmt::format("RPE (evo) delta {} {}{}: translation RMSE {:.6f} m (mean {:.4f}, max {:.4f} m), rotation "
                             "RMSE {:.3f} deg, {} pairs\n",
                             r.options.delta, ev::to_string(r.options.unit), r.options.all_pairs ? ", all pairs" : "",
                             r.translation.rmse, r.translation.mean, r.translation.max, r.rotation_deg.rmse,
                             r.pairs.size());
  }
  if (a.out.empty()) return;

  fs::create_directories(a.out);
  const fs::path json_file = a.out / "eval.json", csv_file = a.out / "eval.csv", png_file = a.out / "eval.png";
  {
    std::ofstream out(json_file);
    out << evaluation_json(a, e).dump(2) << "\n";
    if (!out) throw IoError(json_file.string(), "cannot write");
  }
  write_per_pose(csv_file, e);
  std::cout << "wrote " << json_file.string() << ", " << csv_file.string();
  if (!a.no_plot) {
    run_figure_script("plot_eval.py", {csv_file.string(), "--out", png_file.string(), "--title",
                                       fmt::format("{}: ATE RMSE {:.4f} m ({})", a.est.filename().string(),
                                                   e.ate.position.rmse, ev::to_string(e.ate.alignment))});
    std::cout << ", " << png_file.string();
  }
  std::cout << "\n";
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Trajectory error (ATE, RPE) of an estimate against ground truth");
  auto a = std::make_shared<EvalArgs>();
  cmd->add_option("--est", a->est, "Estimated trajectory (TUM file)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--gt", a->gt, "Ground truth: TUM file, or a recording folder with ground truth")
      ->required()
      ->check(CLI::ExistingPath);
  auto* align = cmd->add_option("--align", a->align,
                                "Alignment before ATE: 4dof (default; posyaw), se3, sim3, scale, none; bare --align is "
                                "se3, as evo's -a")
                    ->expected(0, 1)
                    ->default_str("se3")
                    ->check(CLI::IsMember({"4dof", "posyaw", "se3", "sim3", "scale", "none"}));
  cmd->add_flag("-a", a->evo_align, "evo: SE(3) alignment (--align se3)");
  cmd->add_flag("-s,--correct_scale", a->correct_scale,
                "evo: correct the scale; with -a / --align se3 a Sim(3) alignment, alone the scale only");
  cmd->add_option("--align-frames,--n_to_align", a->align_frames, "Align on the first N matched poses (0 = all)")
      ->capture_default_str();
  cmd->add_option("--tolerance", a->tolerance_s, "Association tolerance [s]")->capture_default_str();
  cmd->add_option("--rpe-lengths", a->rpe_lengths, "RPE sub-trajectory lengths [m]")->delimiter(',');
  cmd->add_option("--rpe-percent", a->rpe_percent, "RPE lengths as % of the ground-truth path")->capture_default_str()->delimiter(',');
  cmd->add_option("--out", a->out, "Folder for eval.json, eval.csv and eval.png");
  cmd->add_option("--t_max_diff", a->t_max_diff_s,
                  "evo: associate by evo's rule (nearest pose, reusable) within this many seconds (evo's default 0.01) "
                  "instead of rpg's with --tolerance");
  cmd->add_option("--delta", a->delta, "evo: RPE with this delta (in --delta_unit), besides rpg's RPE");
  cmd->add_option("--delta_unit", a->delta_unit, "evo: the delta's unit: f (frames), m, d (degrees), r (radians)")
      ->check(CLI::IsMember({"f", "m", "d", "r"}))
      ->capture_default_str();
  cmd->add_flag("--all_pairs", a->all_pairs, "evo: RPE over all pairs, not consecutive ones");
  cmd->add_flag("--pairs_from_reference", a->pairs_from_reference, "evo: choose RPE pairs on the ground truth's poses");
  cmd->add_option("--delta_tol", a->delta_tol, "evo: relative delta tolerance of all-pairs RPE")->capture_default_str();
  cmd->add_flag("--no-plot", a->no_plot, "Do not draw eval.png");
  cmd->callback([a, align] {
    a->align_given = align->count() > 0;
    run_eval(*a);
  });
}

}  // namespace navaid::cli
