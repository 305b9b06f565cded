#pragma once
// The label set lives in core (shared with the semantic map); the simulator's names stay valid.
#include "navaid/core/semantic_classes.hpp"

namespace navaid::simulation {

using navaid::is_valid_semantic_id;
using navaid::kNumSemanticClasses;
using navaid::semantic_class_from_name;
using navaid::semantic_class_info;
using navaid::semantic_class_name;
using navaid::semantic_classes;
using navaid::SemanticClass;
using navaid::SemanticClassInfo;

}  // namespace navaid::simulation
