// navaid info: what a recording, capture or trajectory holds, and what is wrong with it.
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "input_option.hpp"
#include "navaid/io/open_input.hpp"
#include "navaid/io/recording_summary.hpp"
#include "navaid/io/ros_bag.hpp"

namespace navaid::cli {
namespace {

nlohmann::ordered_json track_json(const io::TrackSummary& t) {
  return {{"points", t.points}, {"duration_s", t.duration_s}, {"length_m", t.length_m},
          {"max_excursion_m", t.max_excursion_m}};
}

nlohmann::ordered_json summary_json(const io::RecordingSummary& s) {
  nlohmann::ordered_json j;
  j["path"] = s.path;
  j["format"] = s.format;
  j["streams"] = nlohmann::ordered_json::array();
  for (const auto& st : s.streams) {
    j["streams"].push_back({{"name", st.name},
                            {"count", st.count},
                            {"first_s", format_seconds(st.first)},
                            {"last_s", format_seconds(st.last)},
                            {"duration_s", st.duration_s},
                            {"rate_hz", st.rate_hz},
                            {"nominal_rate_hz", st.nominal_rate_hz},
                            {"gaps", st.gaps},
                            {"longest_gap_s", st.longest_gap_s},
                            {"dropped", st.dropped},
                            {"non_monotonic", st.non_monotonic}});
  }
  if (!s.features.empty()) {
    j["features"] = nlohmann::ordered_json::array();
    for (const auto& f : s.features)
      j["features"].push_back({{"camera", f.camera},
                               {"frames", f.frames},
                               {"empty_frames", f.empty_frames},
                               {"observations", f.observations},
                               {"tracks", f.tracks},
                               {"mean_per_frame", f.mean_per_frame},
                               {"depth_fraction", f.depth_fraction}});
  }
  if (s.landmarks > 0) {
    j["landmarks"] = s.landmarks;
    j["tracks_without_landmark"] = s.tracks_without_landmark;
  }
  if (s.groundtruth) j["groundtruth"] = track_json(*s.groundtruth);
  if (s.gps_track) j["gps_track"] = track_json(*s.gps_track);
  j["gps_fixes_without_position"] = s.gps_fixes_without_position;
  if (s.origin)
    j["origin"] = {{"lat", s.origin->latitude_deg}, {"lon", s.origin->longitude_deg}, {"height_m", s.origin->height_m}};
  j["cameras"] = s.cameras;
  j["imu_calibration"] = s.has_imu_calibration;
  j["warnings"] = nlohmann::ordered_json::array();
  for (const auto& w : s.report.warnings)
    j["warnings"].push_back({{"source", w.source}, {"message", w.message}, {"count", w.count}});
  return j;
}

void print_track(const char* what, const io::TrackSummary& t, const char* unit) {
  std::cout << fmt::format("{:<13}{} {}, {:.1f} s, length {:.2f} m, max distance from start {:.2f} m\n", what,
                           t.points, unit, t.duration_s, t.length_m, t.max_excursion_m);
}

void print_summary(const io::RecordingSummary& s) {
  std::cout << fmt::format("{:<13}{}\n{:<13}{}\n", "recording", s.path, "format", s.format);
  if (s.origin)
    std::cout << fmt::format("{:<13}lat {:.8f} deg, lon {:.8f} deg, h {:.2f} m\n", "origin", s.origin->latitude_deg,
                             s.origin->longitude_deg, s.origin->height_m);
  for (const auto& cam : s.cameras) std::cout << fmt::format("{:<13}{}\n", "camera", cam);
  if (s.has_imu_calibration) std::cout << fmt::format("{:<13}{}\n", "imu", "noise calibration present");
  if (!s.streams.empty()) {
    std::cout << fmt::format("{:<13}{:>8} {:>10} {:>12} {:>22} {:>22} {:>6} {:>8}\n", "stream", "count", "rate [Hz]",
                             "duration [s]", "first [s]", "last [s]", "gaps", "dropped");
    for (const auto& st : s.streams)
      std::cout << fmt::format("{:<13}{:>8} {:>10.3f} {:>12.3f} {:>22} {:>22} {:>6} {:>8}\n", st.name, st.count,
                               st.rate_hz, st.duration_s, format_seconds(st.first), format_seconds(st.last), st.gaps,
                               st.dropped);
  }
  for (const auto& f : s.features)
    std::cout << fmt::format("{:<13}{}: {} frames ({} without features), {:.1f} per frame, {:.1f}% with depth, "
                             "{} tracks\n",
                             "features", f.camera, f.frames, f.empty_frames, f.mean_per_frame,
                             100.0 * f.depth_fraction, f.tracks);
  if (s.landmarks > 0)
    std::cout << fmt::format("{:<13}{} ({} feature tracks without one)\n", "landmarks", s.landmarks,
                             s.tracks_without_landmark);
  if (s.groundtruth) print_track("ground truth", *s.groundtruth, "poses");
  if (s.gps_track) print_track("GNSS track", *s.gps_track, "fixes");
  if (s.gps_fixes_without_position > 0)
    std::cout << fmt::format("{:<13}{} fixes without a position (no fix)\n", "", s.gps_fixes_without_position);
  std::cout << fmt::format("{:<13}{}\n", "warnings", s.report.total());
  for (const auto& w : s.report.warnings)
    std::cout << fmt::format("  {}: {}{}\n", w.source, w.message, w.count > 1 ? fmt::format(" (x{})", w.count) : "");
}

void print_collection_row(const io::RecordingSummary& s) {
  std::size_t samples = 0;
  double duration = 0;
  for (const auto& st : s.streams) {
    samples += st.count;
    duration = std::max(duration, st.duration_s);
  }
  const double length = s.gps_track ? s.gps_track->length_m : s.groundtruth ? s.groundtruth->length_m : 0.0;
  std::cout << fmt::format("{:<44} {:<15} {:>8} {:>10.1f} {:>11.1f} {:>9}\n",
                           std::filesystem::path(s.path).filename().string(), s.format, samples, duration, length,
                           s.report.total());
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Summarise a recording, capture, trajectory or folder of them");
  auto input = std::make_shared<InputOption>();
  auto json = std::make_shared<bool>(false);
  input->add_to(*cmd);
  cmd->add_flag("--json", *json, "Machine-readable JSON on stdout");
  cmd->callback([input, json] {
    const auto kind = input->kind();
    if (kind == io::InputKind::kCollection) {
      const auto members = io::collection_members(input->path);
      nlohmann::ordered_json all = nlohmann::ordered_json::array();
      if (!*json)
        std::cout << fmt::format("collection {} ({} members)\n{:<44} {:<15} {:>8} {:>10} {:>11} {:>9}\n",
                                 input->path.string(), members.size(), "member", "format", "samples", "dur. [s]",
                                 "length [m]", "warnings");
      for (const auto& m : members) {
        const auto s = io::summarize(io::read_input(m));
        if (*json)
          all.push_back(summary_json(s));
        else
          print_collection_row(s);
      }
      if (*json) std::cout << all.dump(2) << "\n";
      return;
    }
    if (kind == io::InputKind::kRosBag && !*json) {  // the topics first: reading may ask to name one
      std::cout << fmt::format("{:<48} {:<40} {:>9}\n", "topic", "type", "messages");
      for (const auto& t : io::list_ros_bag_topics(input->path))
        std::cout << fmt::format("{:<48} {:<40} {:>9}\n", t.topic, t.type, t.messages);
    }
    const auto summary = io::summarize(io::read_input(input->path, kind));
    if (*json) {
      auto j = summary_json(summary);
      if (kind == io::InputKind::kRosBag)
        for (const auto& t : io::list_ros_bag_topics(input->path))
          j["topics"].push_back({{"topic", t.topic}, {"type", t.type}, {"messages", t.messages}});
      std::cout << j.dump(2) << "\n";
      return;
    }
    print_summary(summary);
  });
}

}  // namespace navaid::cli
