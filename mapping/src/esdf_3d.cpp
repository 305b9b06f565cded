#include "navaid/mapping/esdf_3d.hpp"

namespace navaid::mapping {

Esdf3dConfig read_esdf_3d_config(const Config& config) {
  Esdf3dConfig e;
  e.max_distance_m = config.get_double("mapping.esdf3d.max_distance_m", e.max_distance_m, {0.1, 20.0});
  e.unknown_as_occupied = config.get_bool("mapping.esdf3d.unknown_as_occupied", e.unknown_as_occupied);
  return e;
}

// The class template is header-only (any tree type); instantiating it for OctoMap's own tree here
// keeps the header compiling under the library's warnings.
template class Esdf3d<octomap::OcTree>;

}  // namespace navaid::mapping
