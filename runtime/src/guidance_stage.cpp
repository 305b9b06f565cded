#include "navaid/runtime/guidance_stage.hpp"

#include "navaid/runtime/config_schema.hpp"

namespace navaid::runtime {

std::unique_ptr<GuidanceStage> make_guidance_stage(const GuidanceStageContext& context) {
  switch (context.spec.guidance) {
    case GuidanceKind::kRoute: return make_route_guidance_stage(context);
    case GuidanceKind::kWalkingPath: return make_walking_path_stage(context);
    case GuidanceKind::kObstacleRumble: return make_obstacle_rumble_stage(context);
    case GuidanceKind::kHandTarget: return make_hand_target_stage(context);
  }
  return nullptr;
}

ConfigSchema guidance_stages_schema() {
  return route_guidance_stage_schema()
      .add(walking_path_stage_schema())
      .add(obstacle_rumble_stage_schema())
      .add(hand_target_stage_schema());
}

planning::GuidanceCommand waiting_command(Timestamp t, planning::GuidanceReason reason, std::string detail) {
  planning::GuidanceCommand c;
  c.t = t;
  c.action = planning::GuidanceAction::kWait;
  c.reason = reason;
  c.confidence = 0.0;
  c.detail = std::move(detail);
  return c;
}

}  // namespace navaid::runtime
