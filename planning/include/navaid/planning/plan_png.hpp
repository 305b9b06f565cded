#pragma once
// A picture of plans on their cost map: cost as grey (white free, black obstacle, mid grey
// unknown), each plan's path in its own colour with a legend line (planner, length, nodes
// expanded, time), the start as a green disc with a heading tick, the goal as a red disc (or a
// red arrow for a directional subgoal). North (+y) up. Throws IoError when it cannot be written.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "navaid/planning/local_planner.hpp"

namespace navaid::planning {

struct LabelledPlan {
  std::string label;  ///< e.g. the planner's name
  const Plan* plan = nullptr;
};

void write_plan_png(const std::filesystem::path& path, const mapping::CostMap& cost, const PlanningProblem& problem,
                    const std::vector<LabelledPlan>& plans);

}  // namespace navaid::planning
