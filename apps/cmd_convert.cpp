// navaid convert: EuRoC, TUM RGB-D, NMEA captures, TUM trajectories, ROS bags or navaid recordings
// into a navaid recording.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <iostream>

#include "bag_options.hpp"
#include "commands.hpp"
#include "input_option.hpp"
#include "navaid/core/geodesy.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/ros_bag.hpp"
#include "navaid/experiments/progress.hpp"

namespace navaid::cli {

using experiments::Progress;


namespace {

void print_written(const std::filesystem::path& output, const io::Recording& recording) {
  std::cout << fmt::format("wrote {}: {} imu, {} frames, {} gps, {} mag, {} ground-truth samples; {} warnings\n",
                           output.string(), recording.imu.size(), recording.frames.size(), recording.gps.size(),
                           recording.mag.size(), recording.groundtruth.size(), recording.report.total());
  for (const auto& w : recording.report.warnings)
    std::cout << fmt::format("  {}: {}{}\n", w.source, w.message, w.count > 1 ? fmt::format(" (x{})", w.count) : "");
}

}  // namespace

void add_convert_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("convert",
                                 "Convert a recording (EuRoC, TUM RGB-D, NMEA capture, TUM trajectory, ROS bag, navaid) "
                                 "into a navaid recording folder");
  auto input = std::make_shared<InputOption>();
  auto output = std::make_shared<std::filesystem::path>();
  auto overwrite = std::make_shared<bool>(false);
  auto bag = std::make_shared<BagOptions>();
  input->add_to(*cmd);
  bag->add_to(*cmd);
  cmd->add_option("output", *output, "Folder to write the navaid recording into")->required();
  cmd->add_flag("--overwrite", *overwrite, "Replace the recording files in an existing output folder");
  cmd->callback([input, output, overwrite, bag] {
    const auto kind = input->kind();
    if (kind == io::InputKind::kCollection)
      throw UsageError(input->path.string() + " is a folder of several captures or trajectories; convert one file at a time");
    if (kind != io::InputKind::kRosBag && bag->given())
      throw UsageError("--topic, --topics, --bag-preset, --camchain, --imu-noise, --depth-pair-window and --depth-range are for ROS bags; " +
                       input->path.string() + " is a " + std::string(io::to_string(kind)));
    if (kind == io::InputKind::kRosBag) {
      io::RosBagConversion conversion = bag->conversion();
      conversion.overwrite = *overwrite;
      const io::Recording recording = io::convert_ros_bag(input->path, *output, conversion);
      print_written(*output, recording);
      return;
    }
    io::Recording recording = io::read_input(input->path, kind);
    if (recording.empty()) throw IoError(input->path.string(), "holds no samples to convert");
    // A capture has no origin of its own: its first 3D fix becomes the ENU origin.
    if (!recording.origin) recording.origin = origin_from_fixes(recording.gps);
    std::error_code ec;
    if (std::filesystem::exists(*output, ec) && !std::filesystem::is_empty(*output, ec) && !*overwrite)
      throw UsageError(output->string() + " exists and is not empty; pass --overwrite to replace its recording files");
    io::NavaidWriteOptions options;
    options.overwrite = *overwrite;
    Progress progress("writing frames", recording.frames.size());
    options.on_frame_written = [&progress](std::size_t done, std::size_t) { progress.update(done); };
    io::write_navaid_recording(recording, *output, options);
    progress.finish();
    spdlog::info("read {} ({}), wrote {}", input->path.string(), recording.format, output->string());
    print_written(*output, recording);
  });
}

}  // namespace navaid::cli
