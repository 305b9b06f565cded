// Urban-canyon factor for the GNSS model: how much of the low sky the buildings hide.
#include <cmath>

#include "navaid/simulation/scenario.hpp"

namespace navaid::simulation {

double urban_canyon_factor(const RayCaster& static_world, const Vec3& p_W) {
  constexpr int kAzimuths = 24;
  constexpr double kElevationsDeg[] = {15.0, 25.0, 35.0, 45.0};
  int blocked = 0, total = 0;
  for (double el_deg : kElevationsDeg) {
    const double el = el_deg * M_PI / 180.0;
    for (int k = 0; k < kAzimuths; ++k) {
      const double az = 2.0 * M_PI * k / kAzimuths;
      const Vec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      // Small t_min: the receiver sits on the walker, not inside geometry.
      if (static_world.cast(p_W, dir, 2000.0, 1e-3)) ++blocked;
      ++total;
    }
  }
  return static_cast<double>(blocked) / total;
}

}  // namespace navaid::simulation
