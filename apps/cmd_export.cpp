// navaid export: a run folder as a ROS 1 bag for RViz (experiments/run_bag_export.hpp, docs/ros.md).
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/run_bag_export.hpp"

namespace navaid::cli {

void add_export_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("export", "Write a run folder as a ROS 1 bag for RViz: TF, path, pose covariance, "
                                           "map point cloud, obstacle / plan / cue markers");
  auto o = std::make_shared<experiments::RunBagExportOptions>();
  cmd->add_option("--run", o->run, "Run folder of navaid run")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--bag", o->bag, "Bag file to write (replaced)")->required();
  cmd->add_option("--recording", o->recording,
                  "The recording of the run, for the camera's extrinsics (default: the one summary.json names)");
  cmd->add_option("--compression", o->compression, "Chunk compression")
      ->check(CLI::IsMember({"none", "bz2", "lz4"}))
      ->capture_default_str();
  cmd->add_option("--path-rate", o->path_rate_hz, "nav_msgs/Path messages per second of the run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([o] {
    const auto counts = experiments::export_run_bag(*o);
    std::cout << fmt::format("wrote {}:", o->bag.string());
    for (const auto& [topic, n] : counts) std::cout << fmt::format(" {} {}", topic, n);
    std::cout << "\n";
  });
}

}  // namespace navaid::cli
