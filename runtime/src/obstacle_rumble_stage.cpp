// The BYU augmented cane's chain (seed augmented-cane, Ch. 2-3): the PCL obstacle pipeline's scan
// of the newest frame (mapping.obstacles.*, run by the map session) through FICF or CACF and the
// rumble table (Tables 2.1, 2.2). The scan lives in the cane's own frame: it needs the estimate's
// attitude only, no position, so there is nothing to wait for once a scan exists.
#include <array>

#include "navaid/runtime/guidance_stage.hpp"
#include "navaid/runtime/config_schema.hpp"
#include "navaid/planning/byu_cost_functions.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::runtime {
namespace {

const ConfigKey<std::string> kCostFunction{"device.cost_function", std::string("cacf"), {"ficf", "cacf"},
                                           "obstacle-rumble guidance: BYU's cost function"};

class ObstacleRumbleStage final : public GuidanceStage {
 public:
  explicit ObstacleRumbleStage(const GuidanceStageContext& c)
      : function_(*planning::byu_cost_function_from_string(
            get(c.config, kCostFunction))),
        config_(planning::read_byu_cost_config(c.config)) {}

  GuidanceOutput update(const GuidanceInput& in) override {
    GuidanceOutput out;
    out.planner = std::string(planning::to_string(function_));
    if (!in.obstacle_scan) {
      out.command = waiting_command(in.estimate.t, planning::GuidanceReason::kLocating, "no obstacle scan yet");
      return out;
    }
    const planning::ByuCosts costs = planning::byu_costs(*in.obstacle_scan, function_, config_);
    const planning::RumbleState state = planning::rumble_state(costs, planning::byu_thresholds(function_, config_));
    ++states_[static_cast<std::size_t>(state)];
    out.command = planning::rumble_command(in.estimate.t, state);
    return out;
  }

  nlohmann::ordered_json summary() const override {
    nlohmann::ordered_json s = nlohmann::ordered_json::object();
    for (auto st : {planning::RumbleState::kOff, planning::RumbleState::kLeft, planning::RumbleState::kRight,
                    planning::RumbleState::kBoth})
      s[std::string(planning::to_string(st))] = states_[static_cast<std::size_t>(st)];
    return {{"function", std::string(planning::to_string(function_))}, {"rumble_states", s}};
  }

 private:
  planning::ByuCostFunction function_;
  planning::ByuCostConfig config_;
  std::array<std::size_t, 4> states_{};
};

}  // namespace

ConfigSchema obstacle_rumble_stage_schema() {
  return ConfigSchema().add(kCostFunction).add(planning::byu_cost_config_schema());
}

std::unique_ptr<GuidanceStage> make_obstacle_rumble_stage(const GuidanceStageContext& context) {
  return std::make_unique<ObstacleRumbleStage>(context);
}

}  // namespace navaid::runtime
