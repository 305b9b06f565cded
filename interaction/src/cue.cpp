#include "navaid/interaction/cue.hpp"

#include <cmath>

#include "navaid/core/enum_names.hpp"

namespace navaid::interaction {

namespace {

constexpr NameTable<CueKind, 8> kKindNames{{
    {CueKind::kStop, "stop"},
    {CueKind::kObstacle, "obstacle"},
    {CueKind::kArrive, "arrive"},
    {CueKind::kTurn, "turn"},
    {CueKind::kVeer, "veer"},
    {CueKind::kOnCourse, "on-course"},
    {CueKind::kObjectDirection, "object-direction"},
    {CueKind::kSystem, "system"},
}};

constexpr NameTable<CueIntensity, 2> kIntensityNames{{
    {CueIntensity::kLow, "low"},
    {CueIntensity::kHigh, "high"},
}};

}  // namespace

std::string_view to_string(CueKind kind) { return enum_name(kKindNames, kind); }
std::optional<CueKind> cue_kind_from_string(std::string_view name) { return enum_value(kKindNames, name); }

std::string_view to_string(CueIntensity intensity) { return enum_name(kIntensityNames, intensity); }
std::optional<CueIntensity> cue_intensity_from_string(std::string_view name) {
  return enum_value(kIntensityNames, name);
}

int clock_position(double bearing_rad) {
  // Clockwise from ahead: a bearing to the right (negative) is a later hour.
  const long hour = std::lround(-bearing_rad / (M_PI / 6.0)) % 12;
  return static_cast<int>(hour <= 0 ? hour + 12 : hour);
}

double clock_bearing(int hour) { return std::remainder(-(hour % 12) * (M_PI / 6.0), 2.0 * M_PI); }

int default_priority(CueKind kind) {
  switch (kind) {
    case CueKind::kStop: return 100;
    case CueKind::kObstacle: return 80;
    case CueKind::kArrive: return 60;
    case CueKind::kTurn: return 50;
    case CueKind::kObjectDirection: return 45;
    case CueKind::kVeer: return 40;
    case CueKind::kSystem: return 30;
    case CueKind::kOnCourse: return 20;
  }
  return 0;
}

}  // namespace navaid::interaction
