#include "navaid/interaction/actuator_pattern.hpp"

#include "navaid/core/enum_names.hpp"

namespace navaid::interaction {

namespace {

constexpr NameTable<DeviceKind, 4> kActuatorPatternNames{{
    {DeviceKind::kBelt, "belt"},
    {DeviceKind::kHand, "hand"},
    {DeviceKind::kRumble, "rumble"},
    {DeviceKind::kWheel, "wheel"},
}};

}  // namespace

std::string_view to_string(DeviceKind kind) { return enum_name(kActuatorPatternNames, kind); }
std::optional<DeviceKind> device_kind_from_string(std::string_view name) { return enum_value(kActuatorPatternNames, name); }

}  // namespace navaid::interaction
