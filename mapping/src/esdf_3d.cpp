#include "navaid/mapping/esdf_3d.hpp"

#include "navaid/mapping/config_schema.hpp"

namespace navaid::mapping {

namespace {
const ConfigKey<double> kMaxDistance{"mapping.esdf3d.max_distance_m", Esdf3dConfig{}.max_distance_m, {0.1, 20.0},
                                     "3D distances saturate here [m] (bounds the update's work)"};
const ConfigKey<bool> kUnknownAsOccupied{"mapping.esdf3d.unknown_as_occupied", Esdf3dConfig{}.unknown_as_occupied,
                                         "treat unseen voxels as obstacles in the 3D ESDF (conservative)"};
}  // namespace

ConfigSchema esdf_3d_config_schema() { return ConfigSchema().add(kMaxDistance).add(kUnknownAsOccupied); }

Esdf3dConfig read_esdf_3d_config(const Config& config) {
  Esdf3dConfig e;
  e.max_distance_m = get(config, kMaxDistance);
  e.unknown_as_occupied = get(config, kUnknownAsOccupied);
  return e;
}

// The class template is header-only (any tree type); instantiating it for OctoMap's own tree here
// keeps the header compiling under the library's warnings.
template class Esdf3d<octomap::OcTree>;

}  // namespace navaid::mapping
