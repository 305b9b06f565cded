// navaid plot: top view and height of a recording's ground truth and GNSS track (in a local ENU
// frame through GeographicLib), drawn by experiments/figures/plot_tracks.py.
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <iostream>

#include "commands.hpp"
#include "input_option.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/experiments/figure_script.hpp"

namespace navaid::cli {

using experiments::run_figure_script;

namespace fs = std::filesystem;
namespace {

void write_series(const fs::path& file, const std::vector<std::pair<Timestamp, Vec3>>& points) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write plot data");
  out << "t,x,y,z\n";
  for (const auto& [t, p] : points) out << fmt::format("{:.9f},{:.6f},{:.6f},{:.6f}\n", ns_to_seconds(t), p.x(), p.y(), p.z());
}

// ENU positions of the located fixes, relative to the recording's origin or one made from the
// fixes; fixes without a measured height (2D) get NaN up, drawn as a break in the height plot.
std::vector<std::pair<Timestamp, Vec3>> gps_enu(const io::Recording& recording) {
  std::vector<std::pair<Timestamp, Vec3>> points;
  const auto origin = recording.origin ? recording.origin : origin_from_fixes(recording.gps);
  if (!origin) return points;
  const LocalEnuFrame frame(*origin);
  for (const auto& fix : recording.gps) {
    if (fix.mode == GpsFixMode::kNoFix) continue;
    const auto h = ellipsoidal_height_m(fix);
    Vec3 enu = frame.to_enu(fix.latitude_deg, fix.longitude_deg, h.value_or(origin->height_m));
    if (!h) enu.z() = std::numeric_limits<double>::quiet_NaN();
    points.emplace_back(fix.t, enu);
  }
  return points;
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "Plot a recording's ground truth and GNSS track (top view and height)");
  auto input = std::make_shared<InputOption>();
  auto output = std::make_shared<fs::path>();
  input->add_to(*cmd);
  cmd->add_option("--out", *output, "Figure file (.png, .pdf or .svg)")->required();
  cmd->callback([input, output] {
    const auto kind = input->kind();
    if (kind == io::InputKind::kCollection)
      throw UsageError(input->path.string() + " is a folder of several captures or trajectories; plot one file at a time");
    const io::Recording recording = io::read_input(input->path, kind);
    const fs::path data_dir = fs::path(output->string() + ".data");
    fs::create_directories(data_dir);
    std::vector<std::string> args;
    if (!recording.groundtruth.empty()) {
      std::vector<std::pair<Timestamp, Vec3>> points;
      for (const auto& s : recording.groundtruth) points.emplace_back(s.t, s.T_W_B.t);
      write_series(data_dir / "groundtruth.csv", points);
      args.push_back("ground truth=" + (data_dir / "groundtruth.csv").string());
    }
    const auto gps = gps_enu(recording);
    if (!gps.empty()) {
      write_series(data_dir / "gnss_enu.csv", gps);
      args.push_back("GNSS fixes (ENU)=" + (data_dir / "gnss_enu.csv").string());
    }
    if (args.empty())
      throw IoError(input->path.string(), "has neither ground truth nor located GNSS fixes to plot");
    const bool enu_only = recording.groundtruth.empty();
    args.insert(args.end(), {"--out", output->string(), "--title",
                             fmt::format("{} ({})", input->path.filename().string(), recording.format)});
    if (enu_only) args.insert(args.end(), {"--xlabel", "east [m]", "--ylabel", "north [m]", "--zlabel", "up [m]"});
    run_figure_script("plot_tracks.py", args);
    std::cout << "wrote " << output->string() << " (data in " << data_dir.string() << ")\n";
  });
}

}  // namespace navaid::cli
