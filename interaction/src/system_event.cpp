#include "navaid/interaction/system_event.hpp"

#include "navaid/core/enum_names.hpp"

namespace navaid::interaction {

namespace {

constexpr NameTable<SystemEventKind, 9> kSystemEventNames{{
    {SystemEventKind::kInitialized, "initialized"},
    {SystemEventKind::kEstimatorMode, "estimator_mode"},
    {SystemEventKind::kNetworkLost, "network_lost"},
    {SystemEventKind::kNetworkRestored, "network_restored"},
    {SystemEventKind::kLinkLost, "link_lost"},
    {SystemEventKind::kLinkRestored, "link_restored"},
    {SystemEventKind::kCameraFault, "camera_fault"},
    {SystemEventKind::kVoiceCommand, "voice_command"},
    {SystemEventKind::kRouteInstruction, "route_instruction"},
}};

}  // namespace

std::string_view to_string(SystemEventKind kind) { return enum_name(kSystemEventNames, kind); }
std::optional<SystemEventKind> system_event_kind_from_string(std::string_view name) {
  return enum_value(kSystemEventNames, name);
}

}  // namespace navaid::interaction
