#pragma once
// What a simulated user makes of a cue event: the device's pattern as it is felt (which belt
// vibrator, how far the wheel pulls, which remote rumbles) and the words as they are heard
// ("Stop!", "Locating, please wait.", "You have arrived."). Directions come from the actuator, so
// the device's own resolution (five vibrators, two remotes) limits what the person can follow.
// Stop and arrival are told apart by their patterns (all five vibrators pulsing, the wheel's
// brake, the front three pulsing twice; both remotes together mean "stop and find a way").
#include <optional>

#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/simulation/simulated_user.hpp"

namespace navaid::experiments {

/// The instruction a person takes from `event` at time t_s on the trial's clock; none when the
/// event tells them nothing new (a refresh of the same pattern, a system message, a dropped cue).
std::optional<simulation::Instruction> perceive_cue(const interaction::CueEvent& event, double t_s);

}  // namespace navaid::experiments
