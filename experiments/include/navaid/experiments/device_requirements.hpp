#pragma once
// Whether a recording can serve a device: what the device's preset needs (device.needs, a street
// map, a goal) that the recording lacks, said before the run starts.
#include <filesystem>
#include <string>
#include <vector>

#include "navaid/io/recording.hpp"
#include "navaid/runtime/device_spec.hpp"

namespace navaid::experiments {

/// What the recording lacks for the device, in words ("depth images", "GPS fixes", ...); empty
/// when it serves. A route without its OSM file needs a simulated recording.
std::vector<std::string> missing_for_device(const runtime::DeviceSpec& spec, const io::Recording& recording,
                                            const std::filesystem::path& recording_dir);

}  // namespace navaid::experiments
