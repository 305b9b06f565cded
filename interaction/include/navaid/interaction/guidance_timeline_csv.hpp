#pragma once
// The guidance timeline: what planning and the system said, in time order, as CSV. Full-device
// runs write it; `navaid cues` reads it; users can write their own (docs/interaction.md).
//
//   t_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value
//   0.0,event,,,,,,,,initialized,
//   0.1,guidance,go,path-found,0.9,12.5,,,,,
//   3.0,guidance,stop,obstacle-ahead,1,,,,,,
//   4.0,event,,,,,,,,voice_command,go to bus stop
//
// type is guidance or event. Guidance rows: action and reason by their names
// (planning/guidance_command.hpp), confidence in [0, 1], the optional device fields empty when
// absent. Event rows: event by name (system_event.hpp) and its value. Times never decrease.
// '#' lines and blank lines are skipped; a value with a comma is double-quoted.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

#include "navaid/interaction/system_event.hpp"
#include "navaid/planning/guidance_command.hpp"

namespace navaid::interaction {

using GuidanceTimelineEntry = std::variant<planning::GuidanceCommand, SystemEvent>;

/// Timestamp of an entry.
Timestamp entry_time(const GuidanceTimelineEntry& entry);

/// Throws IoError naming the file and line (and column) on anything malformed.
std::vector<GuidanceTimelineEntry> read_guidance_timeline_csv(const std::filesystem::path& file);
std::vector<GuidanceTimelineEntry> parse_guidance_timeline_csv(std::istream& in, const std::string& name);

void write_guidance_timeline_csv(const std::filesystem::path& file, const std::vector<GuidanceTimelineEntry>& entries);

/// write_guidance_timeline_csv one entry at a time, for runs that write the timeline as it is made
/// (the same bytes; a long run keeps none of it). IoError naming the file when it cannot be
/// created (constructor) or a write failed (close()).
class GuidanceTimelineWriter {
 public:
  explicit GuidanceTimelineWriter(const std::filesystem::path& file);
  void add(const GuidanceTimelineEntry& entry);
  void close();
  std::size_t entries() const { return count_; }

 private:
  std::string name_;
  std::ofstream out_;
  std::size_t count_ = 0;
};

}  // namespace navaid::interaction
