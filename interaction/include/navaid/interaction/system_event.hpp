#pragma once
// System events that interaction announces besides guidance: the estimator's mode, the network to
// the segmentation server, the device link, start-up and the user's voice commands.
#include <optional>
#include <string>
#include <string_view>

#include "navaid/core/time.hpp"

namespace navaid::interaction {

enum class SystemEventKind {
  kInitialized,     ///< the system finished initializing
  kEstimatorMode,   ///< value: the estimator mode's name ("RGBD-VIO", "VIO", "IMU-only", ...)
  kNetworkLost,     ///< the segmentation server is unreachable: mapping continues on geometry only
  kNetworkRestored, ///< the segmentation server answers again
  kLinkLost,        ///< the device link to the vibration controller stopped answering
  kLinkRestored,    ///< the device link answers again
  kCameraFault,     ///< value: what failed
  kVoiceCommand,    ///< value: the recognised command ("repeat", "where am i", "go to <place>", ...)
  kRouteInstruction,  ///< value: "<distance_m>;<left|right|straight|cross|steps>[;<road>]" (route narration)
};
std::string_view to_string(SystemEventKind kind);
/// The names to_string gives ("initialized", "estimator_mode", ...); nullopt otherwise.
std::optional<SystemEventKind> system_event_kind_from_string(std::string_view name);

struct SystemEvent {
  Timestamp t = 0;
  SystemEventKind kind = SystemEventKind::kInitialized;
  std::string value;
};

}  // namespace navaid::interaction
