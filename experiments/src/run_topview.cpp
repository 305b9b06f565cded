#include "navaid/experiments/run_topview.hpp"

#include <fmt/format.h>

#include <fstream>
#include <string_view>

#include "navaid/experiments/figure_script.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::experiments {
namespace fs = std::filesystem;
namespace {

struct Point {
  Timestamp t;
  Vec3 p;
  std::string_view mode;  // estimator mode; "truth" for ground truth
};

void write_points(const fs::path& file, const std::vector<Point>& points) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write plot data");
  out << "t,x,y,z,mode\n";
  for (const auto& q : points)
    out << fmt::format("{:.9f},{:.6f},{:.6f},{:.6f},{}\n", ns_to_seconds(q.t), q.p.x(), q.p.y(), q.p.z(), q.mode);
  if (!out) throw IoError(file.string(), "write failed");
}

}  // namespace

void draw_run_topview(const fs::path& run_dir, const std::vector<evaluation::RunEstimate>& estimates,
                      const std::vector<GroundTruthState>& groundtruth,
                      const std::optional<evaluation::Similarity>& W_to_groundtruth, const std::string& title) {
  std::vector<Point> track, enu;
  for (const auto& e : estimates) {
    if (e.mode == EstimatorMode::kInitializing) continue;
    const Timestamp t = e.pose.t;
    const SE3& T_W_B = e.pose.T_W_B;
    if (e.T_ENU_W) enu.push_back({t, (*e.T_ENU_W * T_W_B).t, to_string(e.mode)});
    if (W_to_groundtruth) track.push_back({t, *W_to_groundtruth * T_W_B.t, to_string(e.mode)});
    else if (!e.T_ENU_W) track.push_back({t, T_W_B.t, to_string(e.mode)});
  }
  std::string frame = "W (estimator's world frame)";
  if (W_to_groundtruth) {
    frame = "ground truth's frame (estimate aligned 4-DOF)";
  } else if (!enu.empty()) {
    frame = "ENU (T_ENU_W from GPS; frames before the registration left out)";
    track = std::move(enu);
    enu.clear();
  }
  if (track.empty()) throw Error("no estimate to draw in the top view");

  const fs::path data = run_dir / "topview.data";
  fs::create_directories(data);
  std::vector<std::string> args{"--estimate", (data / "estimate.csv").string()};
  write_points(data / "estimate.csv", track);
  if (W_to_groundtruth && !groundtruth.empty()) {
    std::vector<Point> gt;
    for (const auto& g : groundtruth) gt.push_back({g.t, g.T_W_B.t, "truth"});
    write_points(data / "groundtruth.csv", gt);
    args.insert(args.end(), {"--groundtruth", (data / "groundtruth.csv").string()});
  }
  if (!enu.empty()) {
    write_points(data / "enu.csv", enu);
    args.insert(args.end(), {"--enu", (data / "enu.csv").string()});
  }
  args.insert(args.end(), {"--frame", frame, "--title", title, "--out", (run_dir / "topview.png").string()});
  run_figure_script("plot_run_topview.py", args);
}

}  // namespace navaid::experiments
