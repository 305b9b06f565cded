#pragma once
// Street layouts of the eLabrador routes (elabrador_routes.cpp, beside their builders): the centre
// lines of the sidewalks and roads, the crossings and the named landmarks the worlds are built
// around, for the OSM export (osm_export.hpp).
#include "navaid/simulation/osm_export.hpp"

namespace navaid::simulation::scenarios {

StreetMap route1_streets();
StreetMap route2_streets();

}  // namespace navaid::simulation::scenarios
