#pragma once
// A top view of a foot route (north up, local ENU about the route's start): the walkable ways
// around it in grey (sidewalks and footways light blue, roads dark grey, steps orange), the route in
// red, its crossings as green (signals) / yellow (marked) / magenta (other) discs, start and
// destination discs, landmarks as small black squares, and a legend line. Throws IoError when it
// cannot be written.
#include <filesystem>
#include <string>

#include "navaid/planning/foot_router.hpp"

namespace navaid::planning {

void write_route_png(const std::filesystem::path& path, const FootGraph& graph, const Route& route,
                     const GeoPoint& from, const GeoPoint& to, const std::string& legend);

}  // namespace navaid::planning
