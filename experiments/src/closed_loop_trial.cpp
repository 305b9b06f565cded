#include "navaid/experiments/closed_loop_trial.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <fstream>
#include <random>

#include "navaid/core/config_reads.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/config_schema.hpp"
#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/targets_csv.hpp"
#include "navaid/estimation/estimator_config.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "navaid/runtime/estimator_driver.hpp"
#include "navaid/experiments/cue_perception.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/experiments/trial_device.hpp"
#include "navaid/experiments/experimenter.hpp"
#include "navaid/experiments/reach_protocol.hpp"
#include "navaid/mapping/pose_uncertainty.hpp"
#include "navaid/planning/path_guidance.hpp"
#include "navaid/simulation/config_schema.hpp"
#include "navaid/simulation/online_sensors.hpp"
#include "navaid/simulation/osm_export.hpp"
#include "navaid/simulation/person_motion.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/simulator.hpp"
#include "navaid/core/random_draws.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The mount a device is worn on: the belt's camera on the helmet, the wheel's and the rumble's on
/// the cane, the hand unit's in the hand.
std::string device_mount(interaction::DeviceKind actuator) {
  switch (actuator) {
    case interaction::DeviceKind::kBelt: return "head";
    case interaction::DeviceKind::kWheel:
    case interaction::DeviceKind::kRumble: return "cane";
    case interaction::DeviceKind::kHand: return "hand";
  }
  return "cane";
}

std::ofstream open_csv(const fs::path& file, const char* header) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write");
  out << header << "\n";
  return out;
}

/// The scenario keys of the trial as a simulated recording's simulation.yaml has them, so that the
/// device's stages find the scenario (its streets, its path) as they do for `navaid simulate`'s.
void write_simulation_yaml(const fs::path& file, const std::string& scenario, const simulation::ScenarioOptions& o) {
  std::ofstream y(file);
  if (!y) throw IoError(file.string(), "cannot write");
  y << "# the closed-loop trial's world (navaid trial)\n"
    << "scenario: " << scenario << "\nsimulation:\n  world_seed: " << o.seed << "\n  people: " << (o.people ? "true" : "false")
    << "\n  vehicles: " << (o.vehicles ? "true" : "false") << "\n  targets: " << (o.targets ? "true" : "false")
    << "\n  layout: " << (o.random_layout ? "random" : "default") << "\n";
}

/// What a goal-known person is told of the way: the path's turns sharper than `min_turn_rad`
/// (the corridors and doors of the route), not its small weaves round obstacles, then the goal.
std::vector<simulation::Vec2> route_turns(const std::vector<simulation::Vec2>& path, double min_turn_rad) {
  std::vector<simulation::Vec2> way;
  for (std::size_t i = 1; i + 1 < path.size(); ++i) {
    const simulation::Vec2 a = path[i] - path[i - 1], b = path[i + 1] - path[i];
    const double turn = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    if (std::abs(turn) > min_turn_rad) way.push_back(path[i]);
  }
  way.push_back(path.back());
  return way;
}

/// What the reaching person did (reach_protocol.hpp): search time, closest approach, grasps, cues.
nlohmann::ordered_json reach_summary(const ReachProtocol& reach, bool guided, double end_s) {
  const simulation::ReachCounts& k = reach.counts();
  return {{"guided", guided},
          {"search_start_s", reach.search_start_s() ? nlohmann::ordered_json(*reach.search_start_s()) : nullptr},
          {"search_time_s", reach.search_time_s(end_s)},
          {"closest_m", reach.closest_m()},
          {"failed_grasps", reach.failed_grasps()},
          {"hand_cues", k.hand_cues}, {"ignored", k.ignored}, {"walks", k.walks}, {"turns", k.turns},
          {"grasps", k.grasps}, {"detours", k.detours}, {"spiral_rings", k.rings}};
}

/// Contacts with the world: the body's and the cane's, and by body part.
nlohmann::ordered_json contacts_summary(const TrialResult& r) {
  nlohmann::ordered_json parts = {{"legs", 0}, {"torso", 0}, {"head", 0}, {"cane", 0}};
  for (const auto& c : r.contacts) parts[std::string(to_string(c.part))] = parts[std::string(to_string(c.part))].get<int>() + 1;
  return {{"body", r.body_contacts}, {"cane", r.cane_contacts}, {"by_part", parts}};
}

/// Every instruction that pointed the person into an obstacle (trial.guidance_check_m ahead).
nlohmann::ordered_json into_obstacle_summary(const std::vector<GuidanceIntoObstacle>& events) {
  nlohmann::ordered_json into = nlohmann::ordered_json::array();
  for (const auto& g : events)
    into.push_back({{"t_s", g.t_s}, {"instruction", g.instruction}, {"direction_deg", g.direction_deg},
                    {"primitive", g.primitive}, {"semantic", g.semantic}});
  return into;
}

nlohmann::ordered_json user_counts_summary(const simulation::UserCounts& u, double preferred_speed_mps) {
  return {{"instructions", u.instructions}, {"ignored", u.ignored}, {"corrections", u.corrections},
          {"stops", u.stops}, {"cane_avoidances", u.cane_avoidances}, {"bumps", u.bumps},
          {"preferred_speed_mps", preferred_speed_mps}};
}

}  // namespace

namespace {
const ConfigKey<std::string> kTask{"trial.task", std::nullopt, {"walk", "reach"},
                                   "walk to the goal, or reach for an object; default: reach with a hand-target "
                                   "device, else walk"};
const ConfigKey<int> kRenderWidth{"trial.render_width", std::nullopt, 16, 4096,
                                  "width of the images rendered for the device [px]; default 320 for a reach, else "
                                  "160"};
const ConfigKey<double> kContactRate{"trial.contact_rate_hz", 20.0, {1.0, 1000.0},
                                     "rate of the body's and cane's contact checks [Hz]"};
const ConfigKey<double> kGuidanceCheck{"trial.guidance_check_m", 0.7, {0.05, 10.0},
                                       "a guidance into an obstacle is checked this far ahead [m]"};
const ConfigKey<double> kRouteTurn{"trial.route_turn_deg", 60.0, {0.0, 180.0},
                                   "path corners sharper than this are the person's turn points [deg]"};
const ConfigKey<double> kTurnReach{"trial.turn_reach_m", 0.8, {0.1, 5.0}, "a turn point counts as reached within "
                                                                          "this [m]"};
const ConfigKey<double> kFaceTolerance{"trial.face_tolerance_deg", 45.0, {1.0, 180.0},
                                       "facing the destination's landmark within this [deg]"};
const ConfigKey<double> kTimeout{"trial.timeout_s", std::nullopt, {1.0, 36000.0},
                                 "a trial fails after this [s]; default: 3 x the walk at the user's speed + 20 s (a "
                                 "reach: locate + 60 s + its time limit)"};
const ConfigKey<bool> kFaceLandmark{"trial.face_landmark", std::nullopt,
                                    "success needs facing the destination's landmark (eLabrador); default: with route "
                                    "guidance"};
const ConfigKey<double> kGoalRadius{"trial.goal_radius_m", std::nullopt, {0.1, 10.0},
                                    "arrived within this of the path's end [m]; default 3 when facing a landmark, else "
                                    "0.6"};
const ConfigKey<double> kSettle{"trial.settle_s", 3.0, {0.0, 60.0}, "a route trial ends this long after arrival [s]"};
const ConfigKey<double> kTurnPointSigma{"trial.turn_point_sigma_m", 0.0, {0.0, 50.0},
                                        "error per axis of the turn points a goal-knowing person learns [m]"};
const ConfigKey<bool> kSaveRecording{"trial.save_recording", false,
                                     "write the device's sensor streams and true states as a navaid recording"};
const ConfigKey<double> kWalkOffSpeed{"trial.walk_off_speed_factor", 0.7, {0.1, 1.0},
                                      "route guidance: the person walks off at this share of their speed"};
}  // namespace

ConfigSchema trial_schema() {
  return ConfigSchema()
      .add(kTask)
      .add(kRenderWidth)
      .add(kContactRate)
      .add(kGuidanceCheck)
      .add(kRouteTurn)
      .add(kTurnReach)
      .add(kFaceTolerance)
      .add(frontend_rate_key())
      .add(kTimeout)
      .add(kFaceLandmark)
      .add(kGoalRadius)
      .add(kSettle)
      .add(kTurnPointSigma)
      .add(kSaveRecording)
      .add(kWalkOffSpeed);
}

using runtime::DeviceSpec;
using runtime::GuidanceKind;

TrialResult run_trial(const TrialSpec& spec, const fs::path& out) {
  const auto wall0 = Clock::now();
  Config config = spec.config;
  config.apply_override("scenario=" + spec.scenario);
  config.apply_override(fmt::format("simulation.world_seed={}", spec.world_seed));
  config.apply_override(fmt::format("seed={}", spec.seed));
  const ConfigReads reads(config);  // config.yaml: the given keys and the defaults the trial used
  const bool with_device = config.has("device.name");
  // W-ROMA's task, reaching for an object (reach_protocol.hpp): a hand-target device's by default.
  const bool hand_device = with_device && config.has(runtime::device_guidance_key().name) &&
                           get(config, runtime::device_guidance_key()) == to_string(GuidanceKind::kHandTarget);
  const bool reach_task = get(config, defaulting_to(kTask, std::string(hand_device ? "reach" : "walk"))) == "reach";
  if (reach_task && !config.has("simulation.targets")) config.apply_override("simulation.targets=true");
  // A person searching with the hand points it level (the hand mount's 10 deg pitch is a walk's):
  // the hand unit's aligned cone (5 deg far away) is then reachable.
  if (reach_task && !config.has("mount_pitch_deg")) config.apply_override("mount_pitch_deg=0");
  if (with_device && !config.has("mount")) {
    const auto actuator = interaction::device_kind_from_string(get(config, runtime::device_actuator_key()));
    if (actuator) config.apply_override("mount=" + device_mount(*actuator));
  }
  const simulation::ScenarioOptions scenario_options = simulation::read_scenario_options(config);
  const simulation::Scenario scenario =
      simulation::make_scenario(simulation::read_scenario_name(config), scenario_options);
  if (scenario.kind != simulation::ScenarioKind::kWalk)
    throw UsageError("scenario " + scenario.name + " is a planner map, not a walk: a trial needs a walk scenario");
  simulation::SimulationConfig sim = simulation::read_simulation_config(config, scenario);
  simulation::UserModel user_model = simulation::read_user_model(config);

  // The trial's own keys.
  // The tag detector of a hand-target device needs more pixels than mapping does.
  const int render_width = get(config, defaulting_to(kRenderWidth, reach_task ? 320 : 160));
  const double contact_rate = get(config, kContactRate);
  const double check_m = get(config, kGuidanceCheck);
  const double route_turn_rad = get(config, kRouteTurn) * M_PI / 180.0;
  const double turn_reach_m = get(config, kTurnReach);
  const double face_tolerance = get(config, kFaceTolerance) * M_PI / 180.0;
  const double camera_rate =
      with_device ? get(config, within(defaulting_to(frontend_rate_key(), sim.camera.rate_hz), {1.0, 200.0}))
                  : sim.camera.rate_hz;

  // Start, goal and the nominal walk (the landmarks lie along it; the timeout scales with it).
  const simulation::Vec2 start = scenario.path.front(), goal = scenario.path.back();
  const simulation::Vec2 first_leg = scenario.path[1] - start;
  const double start_heading = std::atan2(first_leg.y(), first_leg.x());
  simulation::WalkerConfig walker = sim.walker;
  walker.ground_z_m = scenario.ground_z_m;
  const simulation::WalkerTrajectory nominal(scenario.path, walker);
  std::optional<ReachProtocol> reach;
  std::optional<simulation::HandMotion> hand;
  if (reach_task) {
    reach.emplace(scenario, read_reach_protocol_config(config), user_model, simulation::read_reach_model(config),
                  with_device, spec.seed);
    hand.emplace(simulation::read_hand_motion_config(config));
  }
  const double timeout_s = get(config, defaulting_to(kTimeout, reach ? reach->config().locate_s + 60.0 +
                                                                          reach->config().time_limit_s  // + the escort
                                                                    : 3.0 * nominal.length() / user_model.speed_mps + 20.0));

  std::optional<DeviceSpec> device;
  if (with_device) {
    if (!config.has("device.goal_start_frame_m")) {
      // The goal in the start pose's frame, as a user would tell the cane where to go.
      const simulation::Vec2 rel = Eigen::Rotation2Dd(-start_heading) * (goal - start);
      config.apply_override(fmt::format("device.goal_start_frame_m=[{:.6f},{:.6f}]", rel.x(), rel.y()));
    }
    device = runtime::read_device_spec(config);
    if ((device->guidance == GuidanceKind::kHandTarget) != reach_task)
      throw ConfigError(config.origin("trial.task"), "trial.task",
                        fmt::format("device {} ({} guidance) does not do the {} task: reach goes with a hand-target "
                                    "device (w-roma) or none, walk with the others",
                                    device->name, to_string(device->guidance), reach_task ? "reach" : "walk"));
  }
  // Cane users find their own way to the goal; so does the augmented cane's user, toward the
  // music source (the cane only warns); a device with a path or route leads.
  const bool goal_known = !reach_task && (!device || device->guidance == GuidanceKind::kObstacleRumble);
  // eLabrador's success (§V-E): arrived and facing the destination's landmark. A route trial ends
  // where the person stops, trial.settle_s after they arrived (the turn to face it).
  const bool needs_facing =
      !reach_task && get(config, defaulting_to(kFaceLandmark, device && device->guidance == GuidanceKind::kRoute));
  std::optional<simulation::Vec2> landmark;
  if (needs_facing) {
    if (!simulation::has_streets(scenario.name))
      throw ConfigError(config.origin("trial.face_landmark"), "trial.face_landmark",
                        "scenario " + scenario.name + " has no destination landmark (route1 and route2 have)");
    const simulation::StreetMap streets = simulation::scenario_streets(scenario);
    landmark = streets.landmarks.at(streets.goal_landmark).xy;
  }
  // Arrived: within this of the path's end (a route's destination as the experimenter judges it).
  const double goal_radius = get(config, defaulting_to(kGoalRadius, needs_facing ? 3.0 : 0.6));
  const double settle_s = get(config, kSettle);
  // A goal-known person's turn points as they learn them on the way (a phone's GPS navigation: the
  // cane users of the eLabrador study followed Amap): each off by this sigma per axis.
  const double turn_point_sigma = get(config, kTurnPointSigma);
  const ExperimenterConfig experimenter_config = read_experimenter_config(config, needs_facing);
  // The device's sensor streams and the true states as a navaid recording (recording/), so that
  // `navaid run` and `navaid eval` replay the estimator on exactly what it met in the trial.
  const bool save_recording = get(config, kSaveRecording);
  if (save_recording && !with_device)
    throw ConfigError(config.origin("trial.save_recording"), "trial.save_recording",
                      "needs a device (--device): a trial without one has no sensors to record");

  // What the camera renders for mapping: the same lens at a lower resolution (trial.render_width).
  CameraCalibration render_camera = sim.camera;
  if (render_width < sim.camera.width) {
    const int h = static_cast<int>(std::lround(1.0 * sim.camera.height * render_width / sim.camera.width));
    render_camera = simulation::rescale_camera(sim.camera, render_width, h);
  }
  sim.render.render_intensity = reach_task;  // mapping reads depth and labels; the tag detector intensity

  fs::create_directories(out);
  write_simulation_yaml(out / "simulation.yaml", scenario.name, scenario_options);
  // The object's tag for the hand-target stage, as a simulated recording has it.
  if (reach_task) simulation::write_scenario_targets(scenario, out / io::kTargetsCsv);

  // The device: the rig's sensors, the estimator on its IMU and feature observations, the
  // full-device pipeline.
  std::deque<simulation::Instruction> felt;
  double trial_clock_s = 0;
  std::optional<TrialDevice> carried;
  if (device) {
    TrialDeviceOptions options;
    options.render_camera = render_camera;
    options.camera_rate_hz = camera_rate;
    options.save_recording = save_recording;
    options.cue_sink = [&felt, &trial_clock_s](const interaction::CueEvent& ev) {
      const double t_s = ns_to_seconds(ev.t - simulation::kSimulationEpoch);
      if (auto i = perceive_cue(ev, std::max(t_s, trial_clock_s))) felt.push_back(*i);
    };
    carried.emplace(*device, config, scenario, sim, nominal, out, options);
  }
  // A device's preset may hold the front end's keys and mapping.enabled: the trial feeds the
  // estimator features and always maps, yet they are its keys.
  ConfigSchema schema = simulation::simulation_config_schema();
  schema.add(simulation::user_model_schema()).add(trial_schema()).add(experimenter_config_schema());
  if (reach_task)
    schema.add(reach_protocol_config_schema())
        .add(simulation::reach_model_schema())
        .add(simulation::hand_motion_config_schema());
  if (device) schema.add(run_schema(&*device));
  config.reject_unknown_keys(schema);
  {
    std::ofstream(out / "config.yaml") << config.dump(reads.defaults());
  }

  // The person.
  simulation::PersonMotionConfig motion = user_model.motion;
  motion.mount_height_m = sim.mount.height_m;
  motion.ground_z_m = scenario.ground_z_m;
  motion.scan_amplitude_rad = sim.mount.scan_amplitude_rad;
  motion.scan_period_s = sim.mount.scan_period_s;
  const std::uint64_t person_seed = spec.seed * 0x9E3779B97F4A7C15ULL + 17;
  simulation::PersonMotion body(motion, reach ? reach->start_position() : start,
                                reach ? reach->start_heading() : start_heading, person_seed);
  const double mount_z = scenario.ground_z_m + sim.mount.height_m;
  // The long cane: swept by cane users and by the augmented cane's user (it is their cane); the
  // Smart Cane rolls its wheel instead. user.cane.enabled says otherwise.
  if (!config.has("user.cane.enabled")) user_model.cane.enabled = goal_known;
  std::vector<simulation::Vec2> way = route_turns(scenario.path, route_turn_rad);
  if (turn_point_sigma > 0) {
    std::mt19937_64 way_rng(person_seed + 2);
    std::normal_distribution<double> n(0.0, turn_point_sigma);
    for (simulation::Vec2& w : way) w += draw_vector<2>([&] { return n(way_rng); });
  }
  simulation::SimulatedUser user(user_model, goal_known, way, turn_reach_m, person_seed + 1);
  if (needs_facing && goal_known) user.stop_at_goal();
  Experimenter experimenter(experimenter_config, scenario.path);
  if (device && device->guidance == GuidanceKind::kRoute)
    user.walk_off(start_heading, get(config, kWalkOffSpeed));
  simulation::ContactMonitor contacts(scenario.world, scenario.ground_z_m, user_model.body, user_model.cane);
  TrialResult r;
  std::ofstream track = open_csv(
      out / "track.csv",
      reach ? "t_s,x,y,heading_deg,speed_mps,veer_deg,est_x,est_y,est_heading_deg,est_mode,est_sigma_xy_m,hand_fwd_m,"
              "hand_left_m,hand_up_m,hand_to_object_m"
            : "t_s,x,y,heading_deg,speed_mps,veer_deg,est_x,est_y,est_heading_deg,est_mode,est_sigma_xy_m");
  std::ofstream instructions = open_csv(out / "instructions.csv", "t_s,kind,value");
  std::ofstream contact_csv = open_csv(out / "contacts.csv", "t_s,part,semantic,moving,primitive,height_m,x,y");
  bool pointing_into_obstacle = false;
  // Where an instruction sends the person, in W, from their true heading; none for stop and wait.
  const auto instructed_heading = [&body](const simulation::Instruction& i) -> std::optional<double> {
    using K = simulation::Instruction::Kind;
    switch (i.kind) {
      case K::kGo:
      case K::kSteer: return body.heading() + i.value;
      case K::kKeepGoing: return body.heading();
      case K::kTurnToward: return body.heading() + (i.value >= 0 ? 1.0 : -1.0) * M_PI / 4;
      default: return std::nullopt;
    }
  };

  const Timestamp imu_dt_ns = seconds_to_ns(1.0 / sim.imu.rate_hz);
  const Timestamp contact_dt_ns = seconds_to_ns(1.0 / contact_rate);
  const Timestamp begin = -seconds_to_ns(sim.still_time_s);
  Timestamp next_contact = begin, next_track = begin;
  double person_s = 0;
  double walking_s = 0;
  std::optional<double> walked_off;
  std::optional<simulation::CaneTouch> bump;
  std::optional<double> arrived_at;
  const double dt = ns_to_seconds(imu_dt_ns);
  for (Timestamp t = begin;; t += imu_dt_ns) {
    const double t_s = ns_to_seconds(t);
    trial_clock_s = t_s;
    auto tp = Clock::now();
    while (!felt.empty()) {
      const simulation::Instruction i = felt.front();
      felt.pop_front();
      instructions << fmt::format("{:.3f},{},{:.4f}\n", i.t_s, to_string(i.kind), i.value);
      if (reach) {
        reach->perceive(i);
        continue;
      }
      user.perceive(i);
      if (const auto heading = instructed_heading(i)) {
        const auto blocked = contacts.blocked_along(body.position(), *heading, check_m);
        if (blocked && !pointing_into_obstacle)
          r.into_obstacle.push_back({i.t_s, std::string(to_string(i.kind)), *heading * 180.0 / M_PI, *blocked,
                                     std::string(simulation::semantic_class_name(
                                         scenario.world.primitive(*blocked).surface.semantic))});
        pointing_into_obstacle = blocked.has_value();
      }
    }
    // Reaching: contacts count, and obstacles stop the body, only while the person searches (a
    // sighted guide leads them before).
    const bool on_own = !reach || reach->phase() == ReachProtocol::Phase::kSearch;
    simulation::MotionCommand command =
        reach ? reach->decide(t_s, body, *hand, mount_z, bump.has_value()) : user.decide(t_s, body, contacts.cane_touch(), bump);
    if (t_s < 0) command.speed_mps = 0;  // the still start
    bump.reset();
    if (t > begin) {
      const simulation::Vec2 from = body.position();
      body.step(command, dt);
      if (hand) hand->step(dt);
      // Walls do not give way: a step into an obstacle ends where it began, and the person feels it.
      if (on_own) bump = contacts.bump(from, body.position(), body.heading());
      if (bump) body.halt_at(from);
    }
    const simulation::KinematicState state =
        hand ? hand->compose(body.state(), body.heading(), body.yaw_rate(), body.yaw_acceleration()) : body.state();
    if (body.speed() > 0.05) {
      walking_s += dt;
      if (!walked_off) walked_off = t_s;
    }
    if (t >= next_contact) {
      next_contact += contact_dt_ns;
      if (t_s >= 0 && !reach)
        if (const auto heading = experimenter.watch(t_s, body.position(), body.speed(), user.arrived())) {
          user.redirect(*heading, experimenter_config.ahead_m, body);
          instructions << fmt::format("{:.3f},experimenter,{:.4f}\n", t_s, *heading);
        }
      const simulation::World moving = simulation::moving_world(scenario.moving, t_s);
      for (const auto& c : on_own ? contacts.update(t_s, body.position(), body.heading(), moving)
                                  : std::vector<simulation::Contact>{}) {
        r.contacts.push_back(c);
        (c.part == simulation::BodyPart::kCane ? r.cane_contacts : r.body_contacts) += 1;
        contact_csv << fmt::format("{:.3f},{},{},{},{},{:.3f},{:.3f},{:.3f}\n", c.t_s, to_string(c.part),
                                   simulation::semantic_class_name(c.semantic), c.moving ? 1 : 0, c.primitive,
                                   c.height_m, c.where_W.x(), c.where_W.y());
      }
    }
    if (t >= next_track) {
      next_track += seconds_to_ns(0.1);
      track << fmt::format("{:.3f},{:.4f},{:.4f},{:.3f},{:.3f},{:.3f}", t_s, body.position().x(), body.position().y(),
                           body.heading() * 180.0 / M_PI, body.speed(), body.veer() * 180.0 / M_PI);
      // What the device believes: its newest estimate, in its own world frame.
      if (const auto& last = carried ? carried->last_estimate() : std::nullopt)
        track << fmt::format(",{:.4f},{:.4f},{:.3f},{},{:.4f}", last->T_W_B.t.x(), last->T_W_B.t.y(),
                             planning::body_yaw(last->T_W_B) * 180.0 / M_PI, to_string(last->mode),
                             mapping::pose_uncertainty(*last).sigma_xy);
      else
        track << ",,,,,";
      // The hand of a reaching person: its offset from the body and how far it is from the object.
      if (reach)
        track << fmt::format(",{:.3f},{:.3f},{:.3f},{:.3f}", hand->offset().x(), hand->offset().y(), hand->offset().z(),
                             reach->distance_to_object(state.T_W_B.t));
      track << "\n";
    }
    person_s += seconds_since(tp);

    if (carried) carried->step(state, t);

    const double to_goal = (body.position() - goal).norm();
    if (reach) {
      reach->check(t_s, state.T_W_B.t);
      if (reach->phase() == ReachProtocol::Phase::kDone) {
        r.success = reach->success();
        r.outcome = reach->outcome();
        break;
      }
    } else if (needs_facing) {
      if (user.arrived() && !arrived_at) arrived_at = t_s;
      if (arrived_at && t_s >= *arrived_at + settle_s) {
        const simulation::Vec2 d = *landmark - body.position();
        r.faced_landmark = std::abs(std::remainder(body.heading() - std::atan2(d.y(), d.x()), 2 * M_PI)) <= face_tolerance;
        r.success = to_goal <= goal_radius && r.faced_landmark;
        r.outcome = r.success ? "arrived" : to_goal <= goal_radius ? "not-facing" : "stopped-short";
        break;
      }
    } else if (to_goal <= goal_radius || user.arrived()) {
      r.success = to_goal <= goal_radius;
      r.outcome = r.success ? "arrived" : "stopped-short";
      break;
    }
    if (t_s >= timeout_s) {
      r.outcome = "timeout";
      break;
    }
  }
  const double end_s = ns_to_seconds(next_track) - 0.1;
  const nlohmann::ordered_json device_summary = carried ? carried->finish() : nlohmann::ordered_json();

  r.duration_s = reach ? reach->search_time_s(end_s) : walked_off ? std::max(0.0, end_s - *walked_off) : 0.0;
  r.path_length_m = body.distance_walked();
  r.mean_speed_mps = walking_s > 0 ? r.path_length_m / walking_s : 0.0;
  r.user = user.counts();
  r.goal_distance_m = (body.position() - goal).norm();
  r.experimenter_corrections = experimenter.corrections();
  r.max_off_route_m = experimenter.max_off_route_m();
  r.wall_s = seconds_since(wall0);

  nlohmann::ordered_json j;
  j["scenario"] = scenario.name;
  j["world_seed"] = scenario.seed;
  j["seed"] = spec.seed;
  j["device"] = device ? device->name : std::string("none");
  j["user"] = user_model.name;
  j["cane"] = user_model.cane.enabled;
  j["success"] = r.success;
  j["outcome"] = r.outcome;
  j["duration_s"] = r.duration_s;
  j["path_length_m"] = r.path_length_m;
  j["nominal_path_m"] = nominal.length();
  j["mean_speed_mps"] = r.mean_speed_mps;
  j["goal_distance_m"] = r.goal_distance_m;
  if (needs_facing) j["faced_landmark"] = r.faced_landmark;
  if (reach) j["reach"] = reach_summary(*reach, with_device, end_s);
  j["experimenter_corrections"] = r.experimenter_corrections;
  j["max_off_route_m"] = r.max_off_route_m;
  j["contacts"] = contacts_summary(r);
  j["guidance_into_obstacle"] = into_obstacle_summary(r.into_obstacle);
  j["user_counts"] = user_counts_summary(r.user, user.preferred_speed());
  const TrialDeviceCounts n = carried ? carried->counts() : TrialDeviceCounts{};
  j["time"] = {{"wall_s", r.wall_s}, {"person_and_contacts_s", person_s}, {"sensors_s", n.sensor_s},
               {"estimator_s", n.estimator_s}, {"device_s", n.device_s}, {"frames", n.frames},
               {"gps_fixes", n.gps_fixes}, {"mag_samples", n.mag_samples}};
  if (carried) {
    j["estimator"] = carried->estimator_summary();
    j["device_run"] = device_summary;
  }
  r.summary = j;
  std::ofstream(out / "summary.json") << j.dump(2) << "\n";
  return r;
}

}  // namespace navaid::experiments
