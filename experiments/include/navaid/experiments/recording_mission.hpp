#pragma once
// The mission a replay gives a device on a recording (runtime/device_mission.hpp), said for the
// user from what the recording holds: eLabrador's streets (device.route.osm, or a simulated
// scenario's own streets exported to OUT/route/) and destination; the Smart Cane's goal (a
// simulated recording's path end, as seen from the true pose when guidance starts); W-ROMA's
// target tag (the recording's targets.csv). Ground truth enters the device only through here.
#include <filesystem>

#include "navaid/core/config.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/runtime/device_mission.hpp"
#include "navaid/runtime/device_spec.hpp"

namespace navaid::experiments {

/// Throws Error naming the recording and the key to set when the recording cannot say it.
runtime::DeviceMission recording_mission(const runtime::DeviceSpec& spec, const Config& config,
                                         const io::Recording& recording, const std::filesystem::path& recording_dir,
                                         const std::filesystem::path& out);

}  // namespace navaid::experiments
