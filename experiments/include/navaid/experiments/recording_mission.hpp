#pragma once
// The mission a replay gives a device on a recording (runtime/device_mission.hpp), said for the
// user from what the recording holds: eLabrador's streets (device.route.osm, or a simulated
// scenario's own streets exported to OUT/route/) and destination; the Smart Cane's goal (a
// simulated recording's path end, as seen from the true pose when guidance starts); W-ROMA's
// target tag (the recording's targets.csv). Ground truth enters the device only through here.
// What the user says while the device runs comes from a file (read_voice_commands); "go to
// <place>" on a route names one of its streets' landmarks (runtime::street_places).
#include <filesystem>
#include <utility>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/interaction/voice_command.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/runtime/device_mission.hpp"
#include "navaid/runtime/device_spec.hpp"

namespace navaid::experiments {

/// Throws Error naming the recording and the key to set when the recording cannot say it.
runtime::DeviceMission recording_mission(const runtime::DeviceSpec& spec, const Config& config,
                                         const io::Recording& recording, const std::filesystem::path& recording_dir,
                                         const std::filesystem::path& out);

/// A voice command at its time [ns], as the user said it.
using TimedVoiceCommand = std::pair<Timestamp, interaction::VoiceCommand>;

/// The voice_command events of a guidance timeline CSV (navaid listen's voice_event.csv), in time
/// order. Throws IoError naming the file for a malformed file, another kind of entry or words that
/// are no command.
std::vector<TimedVoiceCommand> read_voice_commands(const std::filesystem::path& file);

}  // namespace navaid::experiments
