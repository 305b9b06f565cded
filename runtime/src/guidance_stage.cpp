#include "navaid/runtime/guidance_stage.hpp"

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
