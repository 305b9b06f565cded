#pragma once
// The cue timeline as CSV: every scheduler event, one line each (docs/interaction.md):
//   t_s,channel,outcome,kind,priority,direction_deg,steering_deg,rumble,hand,message,text,duration_s,pattern
// pattern: "off" for all actuators off, else ';'-separated actuator:level:on_ms:off_ms:hold_ms.
#include <filesystem>
#include <string>
#include <vector>

#include "navaid/interaction/cue_scheduler.hpp"

namespace navaid::interaction {

/// "off", or "2:1000:200:300:1250;..." (actuator:level:on_ms:off_ms:hold_ms).
std::string format_pattern(const ActuatorPattern& pattern);

void write_cue_timeline_csv(const std::filesystem::path& file, const std::vector<CueEvent>& events);

}  // namespace navaid::interaction
