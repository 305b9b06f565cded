// The navaid command-line program.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include <Eigen/Core>
#if __has_include(<ceres/version.h>)
#include <ceres/version.h>
#endif

#include "commands.hpp"
#include "navaid/core/allocator.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::cli {
namespace {
// The version, the build type and the numerical libraries the estimates depend on: what a
// results table needs to say which navaid made it.
std::string version_text() {
  std::string text = std::string("navaid ") + NAVAID_VERSION + " (" +
                     (std::string(NAVAID_BUILD_TYPE).empty() ? std::string("no build type") : NAVAID_BUILD_TYPE) +
                     " build; Eigen " + std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
                     "." + std::to_string(EIGEN_MINOR_VERSION);
#ifdef CERES_VERSION_STRING
  text += std::string(", Ceres ") + CERES_VERSION_STRING;
#endif
  return text + ")";
}
}  // namespace
}  // namespace navaid::cli

int main(int argc, char** argv) {
  navaid::keep_freed_memory();
  CLI::App app{"navaid: navigation aids for blind and low-vision people.\n"
               "Reads recordings (navaid, EuRoC/ASL, TUM RGB-D, NMEA captures, TUM trajectories) and simulates new ones."};
  app.set_help_all_flag("--help-all", "Help for every command");
  app.set_version_flag("--version", navaid::cli::version_text());
  int verbosity = 0;
  app.add_flag("-v,--verbose", verbosity, "More log output (repeat for debug)");
  app.require_subcommand(1);
  navaid::cli::add_info_command(app);
  navaid::cli::add_convert_command(app);
  navaid::cli::add_export_command(app);
  navaid::cli::add_plot_command(app);
  navaid::cli::add_simulate_command(app);
  navaid::cli::add_scenario_map_command(app);
  navaid::cli::add_run_command(app);
  navaid::cli::add_eval_command(app);
  navaid::cli::add_ablate_command(app);
  navaid::cli::add_reproduce_command(app);
  navaid::cli::add_consistency_command(app);
  navaid::cli::add_init_study_command(app);
  navaid::cli::add_map_command(app);
  navaid::cli::add_plan_command(app);
  navaid::cli::add_rumble_command(app);
  navaid::cli::add_hand_guide_command(app);
  navaid::cli::add_route_command(app);
  navaid::cli::add_cues_command(app);
  navaid::cli::add_listen_command(app);
  navaid::cli::add_device_sim_command(app);
  navaid::cli::add_trial_command(app);
  navaid::cli::add_config_command(app);
  app.parse_complete_callback([&] {
    spdlog::set_level(verbosity >= 2 ? spdlog::level::debug
                      : verbosity == 1 ? spdlog::level::info
                                       : spdlog::level::warn);
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const navaid::Error& e) {
    std::fprintf(stderr, "navaid: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navaid: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
