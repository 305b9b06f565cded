#pragma once
// The configuration keys the estimation room reads (navaid/core/config_schema.hpp).
#include "navaid/core/config_schema.hpp"

namespace navaid::estimation {

ConfigSchema estimator_config_schema();  ///< read_estimator_config (estimator.*)
ConfigSchema frontend_config_schema();   ///< read_frontend_config (frontend.*)

/// Every key of the estimation room.
ConfigSchema config_schema();

}  // namespace navaid::estimation
