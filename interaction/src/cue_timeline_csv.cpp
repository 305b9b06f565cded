#include "navaid/interaction/cue_timeline_csv.hpp"

#include <fmt/format.h>

#include <fstream>

#include "navaid/core/csv_field.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::interaction {

namespace {

std::string optional_deg(const std::optional<double>& rad) {
  return rad ? fmt::format("{:.3f}", planning::rad_to_deg(*rad)) : "";
}

}  // namespace

std::string format_pattern(const ActuatorPattern& pattern) {
  if (pattern.commands.empty()) return "off";
  std::string s;
  for (const ActuatorCommand& c : pattern.commands) {
    if (!s.empty()) s += ';';
    s += fmt::format("{}:{}:{}:{}:{}", c.actuator, c.level, c.on_ms, c.off_ms, c.hold_ms);
  }
  return s;
}

void write_cue_timeline_csv(const std::filesystem::path& file, const std::vector<CueEvent>& events) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write");
  out << "t_s,channel,outcome,kind,priority,direction_deg,steering_deg,rumble,hand,message,text,duration_s,pattern\n";
  for (const CueEvent& e : events) {
    const Cue& c = e.cue;
    out << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", format_seconds(e.t), to_string(e.channel),
                       to_string(e.outcome), to_string(c.kind), c.priority, optional_deg(c.direction_rad),
                       optional_deg(c.steering_rad), c.rumble ? std::string(planning::to_string(*c.rumble)) : "",
                       c.hand ? std::string(planning::to_string(*c.hand)) : "", c.message ? c.message->id : "",
                       csv_field(e.text), e.outcome == CueOutcome::kSpoken ? fmt::format("{:.3f}", e.duration_s) : "",
                       e.pattern ? format_pattern(*e.pattern) : "");
  }
  if (!out) throw IoError(file.string(), "write failed");
}

}  // namespace navaid::interaction
