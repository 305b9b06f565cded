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

#include "csv_output.hpp"

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

namespace {

/// Configure: what a trial is made of, read from its configuration once (in the order its
/// config.yaml lists the defaults used).
struct TrialSetup {
  bool with_device = false, reach_task = false;
  simulation::ScenarioOptions scenario_options;
  simulation::Scenario scenario;
  simulation::SimulationConfig sim;
  simulation::UserModel user_model;
  double contact_rate = 0, check_m = 0, route_turn_rad = 0, turn_reach_m = 0, face_tolerance = 0, camera_rate = 0;
  simulation::Vec2 start, goal;
  double start_heading = 0;
  std::optional<simulation::WalkerTrajectory> nominal;  ///< the landmarks lie along it; the timeout scales with it
  std::optional<ReachProtocol> reach;
  std::optional<simulation::HandMotion> hand;
  double timeout_s = 0;
  std::optional<DeviceSpec> device;
  bool goal_known = false, needs_facing = false;
  std::optional<simulation::Vec2> landmark;
  double goal_radius = 0, settle_s = 0, turn_point_sigma = 0;
  ExperimenterConfig experimenter_config;
  bool save_recording = false;
  CameraCalibration render_camera;  ///< what the camera renders for mapping
};

/// The device and the task it is for; the goal a user would tell the cane.
void configure_device(TrialSetup& s, Config& config) {
  if (!s.with_device) return;
  if (!config.has("device.goal_start_frame_m")) {
    // The goal in the start pose's frame, as a user would tell the cane where to go.
    const simulation::Vec2 rel = Eigen::Rotation2Dd(-s.start_heading) * (s.goal - s.start);
    config.apply_override(fmt::format("device.goal_start_frame_m=[{:.6f},{:.6f}]", rel.x(), rel.y()));
  }
  s.device = runtime::read_device_spec(config);
  if ((s.device->guidance == GuidanceKind::kHandTarget) != s.reach_task)
    throw ConfigError(config.origin("trial.task"), "trial.task",
                      fmt::format("device {} ({} guidance) does not do the {} task: reach goes with a hand-target "
                                  "device (w-roma) or none, walk with the others",
                                  s.device->name, to_string(s.device->guidance), s.reach_task ? "reach" : "walk"));
}

/// Who knows the goal, and what counts as arriving.
void configure_success(TrialSetup& s, const Config& config) {
  // Cane users find their own way to the goal; so does the augmented cane's user, toward the
  // music source (the cane only warns); a device with a path or route leads.
  s.goal_known = !s.reach_task && (!s.device || s.device->guidance == GuidanceKind::kObstacleRumble);
  // eLabrador's success (§V-E): arrived and facing the destination's landmark. A route trial ends
  // where the person stops, trial.settle_s after they arrived (the turn to face it).
  s.needs_facing =
      !s.reach_task && get(config, defaulting_to(kFaceLandmark, s.device && s.device->guidance == GuidanceKind::kRoute));
  if (s.needs_facing) {
    if (!simulation::has_streets(s.scenario.name))
      throw ConfigError(config.origin("trial.face_landmark"), "trial.face_landmark",
                        "scenario " + s.scenario.name + " has no destination landmark (route1 and route2 have)");
    const simulation::StreetMap streets = simulation::scenario_streets(s.scenario);
    s.landmark = streets.landmarks.at(streets.goal_landmark).xy;
  }
  // Arrived: within this of the path's end (a route's destination as the experimenter judges it).
  s.goal_radius = get(config, defaulting_to(kGoalRadius, s.needs_facing ? 3.0 : 0.6));
  s.settle_s = get(config, kSettle);
  // A goal-known person's turn points as they learn them on the way (a phone's GPS navigation: the
  // cane users of the eLabrador study followed Amap): each off by this sigma per axis.
  s.turn_point_sigma = get(config, kTurnPointSigma);
  s.experimenter_config = read_experimenter_config(config, s.needs_facing);
}

/// The world, the person, the device and the rules of the trial; the defaults the trial fills in
/// (the task's, the mount, the goal told to the cane) become overrides of `config`.
void configure(TrialSetup& s, Config& config, const TrialSpec& spec) {
  s.with_device = config.has("device.name");
  // W-ROMA's task, reaching for an object (reach_protocol.hpp): a hand-target device's by default.
  const bool hand_device = s.with_device && config.has(runtime::device_guidance_key().name) &&
                           get(config, runtime::device_guidance_key()) == to_string(GuidanceKind::kHandTarget);
  s.reach_task = get(config, defaulting_to(kTask, std::string(hand_device ? "reach" : "walk"))) == "reach";
  if (s.reach_task && !config.has("simulation.targets")) config.apply_override("simulation.targets=true");
  // A person searching with the hand points it level (the hand mount's 10 deg pitch is a walk's):
  // the hand unit's aligned cone (5 deg far away) is then reachable.
  if (s.reach_task && !config.has("mount_pitch_deg")) config.apply_override("mount_pitch_deg=0");
  if (s.with_device && !config.has("mount")) {
    const auto actuator = interaction::device_kind_from_string(get(config, runtime::device_actuator_key()));
    if (actuator) config.apply_override("mount=" + device_mount(*actuator));
  }
  s.scenario_options = simulation::read_scenario_options(config);
  s.scenario = simulation::make_scenario(simulation::read_scenario_name(config), s.scenario_options);
  if (s.scenario.kind != simulation::ScenarioKind::kWalk)
    throw UsageError("scenario " + s.scenario.name + " is a planner map, not a walk: a trial needs a walk scenario");
  s.sim = simulation::read_simulation_config(config, s.scenario);
  s.user_model = simulation::read_user_model(config);

  // The trial's own keys.
  // The tag detector of a hand-target device needs more pixels than mapping does.
  const int render_width = get(config, defaulting_to(kRenderWidth, s.reach_task ? 320 : 160));
  s.contact_rate = get(config, kContactRate);
  s.check_m = get(config, kGuidanceCheck);
  s.route_turn_rad = get(config, kRouteTurn) * M_PI / 180.0;
  s.turn_reach_m = get(config, kTurnReach);
  s.face_tolerance = get(config, kFaceTolerance) * M_PI / 180.0;
  s.camera_rate = s.with_device
                      ? get(config, within(defaulting_to(frontend_rate_key(), s.sim.camera.rate_hz), {1.0, 200.0}))
                      : s.sim.camera.rate_hz;

  // Start, goal and the nominal walk.
  s.start = s.scenario.path.front();
  s.goal = s.scenario.path.back();
  const simulation::Vec2 first_leg = s.scenario.path[1] - s.start;
  s.start_heading = std::atan2(first_leg.y(), first_leg.x());
  simulation::WalkerConfig walker = s.sim.walker;
  walker.ground_z_m = s.scenario.ground_z_m;
  s.nominal.emplace(s.scenario.path, walker);
  if (s.reach_task) {
    s.reach.emplace(s.scenario, read_reach_protocol_config(config), s.user_model, simulation::read_reach_model(config),
                    s.with_device, spec.seed);
    s.hand.emplace(simulation::read_hand_motion_config(config));
  }
  s.timeout_s = get(config, defaulting_to(kTimeout, s.reach ? s.reach->config().locate_s + 60.0 +
                                                                  s.reach->config().time_limit_s  // + the escort
                                                            : 3.0 * s.nominal->length() / s.user_model.speed_mps + 20.0));
  configure_device(s, config);
  configure_success(s, config);
  // The device's sensor streams and the true states as a navaid recording (recording/), so that
  // `navaid run` and `navaid eval` replay the estimator on exactly what it met in the trial.
  s.save_recording = get(config, kSaveRecording);
  if (s.save_recording && !s.with_device)
    throw ConfigError(config.origin("trial.save_recording"), "trial.save_recording",
                      "needs a device (--device): a trial without one has no sensors to record");

  // What the camera renders for mapping: the same lens at a lower resolution (trial.render_width).
  s.render_camera = s.sim.camera;
  if (render_width < s.sim.camera.width) {
    const int h = static_cast<int>(std::lround(1.0 * s.sim.camera.height * render_width / s.sim.camera.width));
    s.render_camera = simulation::rescale_camera(s.sim.camera, render_width, h);
  }
  s.sim.render.render_intensity = s.reach_task;  // mapping reads depth and labels; the tag detector intensity
}

/// A device's preset may hold the front end's keys and mapping.enabled: the trial feeds the
/// estimator features and always maps, yet they are its keys.
void reject_unknown_trial_keys(const Config& config, const TrialSetup& s) {
  ConfigSchema schema = simulation::simulation_config_schema();
  schema.add(simulation::user_model_schema()).add(trial_schema()).add(experimenter_config_schema());
  if (s.reach_task)
    schema.add(reach_protocol_config_schema())
        .add(simulation::reach_model_schema())
        .add(simulation::hand_motion_config_schema());
  if (s.device) schema.add(run_schema(&*s.device));
  config.reject_unknown_keys(schema);
}

double walk_off_speed(const Config& config) { return get(config, kWalkOffSpeed); }

/// The trial's person, one IMU tick at a time: what they feel of the device's cues, how they
/// decide and move, what their body and cane touch, what the experimenter does, the files that
/// log it (track.csv, instructions.csv, contacts.csv), and when the trial ends.
class TrialWalk {
 public:
  TrialWalk(TrialSetup& setup, const Config& config, std::uint64_t seed, const fs::path& out)
      : s_(setup),
        person_seed_(seed * 0x9E3779B97F4A7C15ULL + 17),
        model_(cane_user(setup, config)),
        body_(person_motion(setup), setup.reach ? setup.reach->start_position() : setup.start,
              setup.reach ? setup.reach->start_heading() : setup.start_heading, person_seed_),
        mount_z_(setup.scenario.ground_z_m + setup.sim.mount.height_m),
        user_(model_, setup.goal_known, turn_points(setup), setup.turn_reach_m, person_seed_ + 1),
        experimenter_(setup.experimenter_config, setup.scenario.path),
        contacts_(setup.scenario.world, setup.scenario.ground_z_m, model_.body, model_.cane),
        track_(open_csv(out / "track.csv", setup.reach ? "t_s,x,y,heading_deg,speed_mps,veer_deg,est_x,est_y,"
                                                         "est_heading_deg,est_mode,est_sigma_xy_m,hand_fwd_m,"
                                                         "hand_left_m,hand_up_m,hand_to_object_m"
                                                       : "t_s,x,y,heading_deg,speed_mps,veer_deg,est_x,est_y,"
                                                         "est_heading_deg,est_mode,est_sigma_xy_m")),
        instructions_(open_csv(out / "instructions.csv", "t_s,kind,value")),
        contact_csv_(open_csv(out / "contacts.csv", "t_s,part,semantic,moving,primitive,height_m,x,y")),
        imu_dt_(seconds_to_ns(1.0 / setup.sim.imu.rate_hz)),
        contact_dt_(seconds_to_ns(1.0 / setup.contact_rate)),
        begin_(-seconds_to_ns(setup.sim.still_time_s)),
        next_contact_(begin_),
        next_track_(begin_) {
    if (s_.needs_facing && s_.goal_known) user_.stop_at_goal();
    if (s_.device && s_.device->guidance == GuidanceKind::kRoute) user_.walk_off(s_.start_heading, walk_off_speed(config));
  }

  Timestamp begin() const { return begin_; }
  Timestamp imu_dt() const { return imu_dt_; }

  /// The person at `t`: feels the instructions due, decides and moves; the experimenter watches,
  /// contacts are counted and the track logged (with what `carried` believes). Returns the true
  /// state the rig samples.
  simulation::KinematicState move(Timestamp t, std::deque<simulation::Instruction>& felt, const TrialDevice* carried) {
    const double t_s = ns_to_seconds(t);
    const auto t0 = Clock::now();
    while (!felt.empty()) {
      feel(felt.front());
      felt.pop_front();
    }
    // Reaching: contacts count, and obstacles stop the body, only while the person searches (a
    // sighted guide leads them before).
    const bool on_own = !s_.reach || s_.reach->phase() == ReachProtocol::Phase::kSearch;
    simulation::MotionCommand command = s_.reach ? s_.reach->decide(t_s, body_, *s_.hand, mount_z_, bump_.has_value())
                                                 : user_.decide(t_s, body_, contacts_.cane_touch(), bump_);
    if (t_s < 0) command.speed_mps = 0;  // the still start
    bump_.reset();
    const double dt = ns_to_seconds(imu_dt_);
    if (t > begin_) {
      const simulation::Vec2 from = body_.position();
      body_.step(command, dt);
      if (s_.hand) s_.hand->step(dt);
      // Walls do not give way: a step into an obstacle ends where it began, and the person feels it.
      if (on_own) bump_ = contacts_.bump(from, body_.position(), body_.heading());
      if (bump_) body_.halt_at(from);
    }
    const simulation::KinematicState state =
        s_.hand ? s_.hand->compose(body_.state(), body_.heading(), body_.yaw_rate(), body_.yaw_acceleration())
                : body_.state();
    if (body_.speed() > 0.05) {
      walking_s_ += dt;
      if (!walked_off_) walked_off_ = t_s;
    }
    if (t >= next_contact_) {
      next_contact_ += contact_dt_;
      watch(t_s, on_own);
    }
    if (t >= next_track_) {
      next_track_ += seconds_to_ns(0.1);
      log_track(t_s, state, carried ? carried->last_estimate() : std::nullopt);
    }
    person_s_ += seconds_since(t0);
    return state;
  }

  /// Whether the trial ends at `t_s` (the reach done, arrived and settled, arrived, timed out),
  /// with its outcome.
  bool ended(double t_s, const simulation::KinematicState& state) {
    const double to_goal = (body_.position() - s_.goal).norm();
    if (s_.reach) {
      s_.reach->check(t_s, state.T_W_B.t);
      if (s_.reach->phase() == ReachProtocol::Phase::kDone) {
        r_.success = s_.reach->success();
        r_.outcome = s_.reach->outcome();
        return true;
      }
    } else if (s_.needs_facing) {
      if (user_.arrived() && !arrived_at_) arrived_at_ = t_s;
      if (arrived_at_ && t_s >= *arrived_at_ + s_.settle_s) {
        const simulation::Vec2 d = *s_.landmark - body_.position();
        r_.faced_landmark =
            std::abs(std::remainder(body_.heading() - std::atan2(d.y(), d.x()), 2 * M_PI)) <= s_.face_tolerance;
        r_.success = to_goal <= s_.goal_radius && r_.faced_landmark;
        r_.outcome = r_.success ? "arrived" : to_goal <= s_.goal_radius ? "not-facing" : "stopped-short";
        return true;
      }
    } else if (to_goal <= s_.goal_radius || user_.arrived()) {
      r_.success = to_goal <= s_.goal_radius;
      r_.outcome = r_.success ? "arrived" : "stopped-short";
      return true;
    }
    if (t_s >= s_.timeout_s) {
      r_.outcome = "timeout";
      return true;
    }
    return false;
  }

  /// Evaluate: the walk's result once it ended.
  TrialResult result(double wall_s) {
    const double end_s = this->end_s();
    r_.duration_s = s_.reach ? s_.reach->search_time_s(end_s) : walked_off_ ? std::max(0.0, end_s - *walked_off_) : 0.0;
    r_.path_length_m = body_.distance_walked();
    r_.mean_speed_mps = walking_s_ > 0 ? r_.path_length_m / walking_s_ : 0.0;
    r_.user = user_.counts();
    r_.goal_distance_m = (body_.position() - s_.goal).norm();
    r_.experimenter_corrections = experimenter_.corrections();
    r_.max_off_route_m = experimenter_.max_off_route_m();
    r_.wall_s = wall_s;
    return r_;
  }

  double end_s() const { return ns_to_seconds(next_track_) - 0.1; }
  double person_s() const { return person_s_; }
  double preferred_speed() const { return user_.preferred_speed(); }
  const simulation::UserModel& user_model() const { return model_; }

 private:
  static simulation::PersonMotionConfig person_motion(const TrialSetup& s) {
    simulation::PersonMotionConfig motion = s.user_model.motion;
    motion.mount_height_m = s.sim.mount.height_m;
    motion.ground_z_m = s.scenario.ground_z_m;
    motion.scan_amplitude_rad = s.sim.mount.scan_amplitude_rad;
    motion.scan_period_s = s.sim.mount.scan_period_s;
    return motion;
  }

  /// The long cane: swept by cane users and by the augmented cane's user (it is their cane); the
  /// Smart Cane rolls its wheel instead. user.cane.enabled says otherwise.
  static simulation::UserModel cane_user(const TrialSetup& s, const Config& config) {
    simulation::UserModel model = s.user_model;
    if (!config.has("user.cane.enabled")) model.cane.enabled = s.goal_known;
    return model;
  }

  std::vector<simulation::Vec2> turn_points(const TrialSetup& s) const {
    std::vector<simulation::Vec2> way = route_turns(s.scenario.path, s.route_turn_rad);
    if (s.turn_point_sigma > 0) {
      std::mt19937_64 way_rng(person_seed_ + 2);
      std::normal_distribution<double> n(0.0, s.turn_point_sigma);
      for (simulation::Vec2& w : way) w += draw_vector<2>([&] { return n(way_rng); });
    }
    return way;
  }

  /// An instruction reaches the person (or the reaching protocol); one that points them into an
  /// obstacle is counted once per episode.
  void feel(const simulation::Instruction& i) {
    instructions_ << fmt::format("{:.3f},{},{:.4f}\n", i.t_s, to_string(i.kind), i.value);
    if (s_.reach) {
      s_.reach->perceive(i);
      return;
    }
    user_.perceive(i);
    const auto heading = instructed_heading(i);
    if (!heading) return;
    const auto blocked = contacts_.blocked_along(body_.position(), *heading, s_.check_m);
    if (blocked && !pointing_into_obstacle_)
      r_.into_obstacle.push_back({i.t_s, std::string(to_string(i.kind)), *heading * 180.0 / M_PI, *blocked,
                                  std::string(simulation::semantic_class_name(
                                      s_.scenario.world.primitive(*blocked).surface.semantic))});
    pointing_into_obstacle_ = blocked.has_value();
  }

  /// Where an instruction sends the person, in W, from their true heading; none for stop and wait.
  std::optional<double> instructed_heading(const simulation::Instruction& i) const {
    using K = simulation::Instruction::Kind;
    switch (i.kind) {
      case K::kGo:
      case K::kSteer: return body_.heading() + i.value;
      case K::kKeepGoing: return body_.heading();
      case K::kTurnToward: return body_.heading() + (i.value >= 0 ? 1.0 : -1.0) * M_PI / 4;
      default: return std::nullopt;
    }
  }

  /// At the contact rate: the experimenter's corrections and the contacts that begin.
  void watch(double t_s, bool on_own) {
    if (t_s >= 0 && !s_.reach)
      if (const auto heading = experimenter_.watch(t_s, body_.position(), body_.speed(), user_.arrived())) {
        user_.redirect(*heading, s_.experimenter_config.ahead_m, body_);
        instructions_ << fmt::format("{:.3f},experimenter,{:.4f}\n", t_s, *heading);
      }
    if (!on_own) return;
    const simulation::World moving = simulation::moving_world(s_.scenario.moving, t_s);
    for (const auto& c : contacts_.update(t_s, body_.position(), body_.heading(), moving)) {
      r_.contacts.push_back(c);
      (c.part == simulation::BodyPart::kCane ? r_.cane_contacts : r_.body_contacts) += 1;
      contact_csv_ << fmt::format("{:.3f},{},{},{},{},{:.3f},{:.3f},{:.3f}\n", c.t_s, to_string(c.part),
                                  simulation::semantic_class_name(c.semantic), c.moving ? 1 : 0, c.primitive,
                                  c.height_m, c.where_W.x(), c.where_W.y());
    }
  }

  /// A track.csv row: the true walk, what the device believes (its newest estimate, in its own
  /// world frame) and, reaching, the hand.
  void log_track(double t_s, const simulation::KinematicState& state, const std::optional<StateEstimate>& last) {
    track_ << fmt::format("{:.3f},{:.4f},{:.4f},{:.3f},{:.3f},{:.3f}", t_s, body_.position().x(), body_.position().y(),
                          body_.heading() * 180.0 / M_PI, body_.speed(), body_.veer() * 180.0 / M_PI);
    if (last)
      track_ << fmt::format(",{:.4f},{:.4f},{:.3f},{},{:.4f}", last->T_W_B.t.x(), last->T_W_B.t.y(),
                            planning::body_yaw(last->T_W_B) * 180.0 / M_PI, to_string(last->mode),
                            mapping::pose_uncertainty(*last).sigma_xy);
    else
      track_ << ",,,,,";
    if (s_.reach)
      track_ << fmt::format(",{:.3f},{:.3f},{:.3f},{:.3f}", s_.hand->offset().x(), s_.hand->offset().y(),
                            s_.hand->offset().z(), s_.reach->distance_to_object(state.T_W_B.t));
    track_ << "\n";
  }

  TrialSetup& s_;
  std::uint64_t person_seed_;
  simulation::UserModel model_;  ///< the trial's user, with the long cane when they sweep one
  simulation::PersonMotion body_;
  double mount_z_;
  simulation::SimulatedUser user_;
  Experimenter experimenter_;
  simulation::ContactMonitor contacts_;
  std::ofstream track_, instructions_, contact_csv_;
  Timestamp imu_dt_, contact_dt_, begin_, next_contact_, next_track_;
  TrialResult r_;
  bool pointing_into_obstacle_ = false;
  double person_s_ = 0, walking_s_ = 0;
  std::optional<double> walked_off_, arrived_at_;
  std::optional<simulation::CaneTouch> bump_;
};

/// Report: summary.json's contents.
nlohmann::ordered_json trial_summary(const TrialSpec& spec, const TrialSetup& s, const TrialWalk& walk,
                                     const TrialResult& r, const TrialDevice* carried,
                                     const nlohmann::ordered_json& device_summary) {
  nlohmann::ordered_json j;
  j["scenario"] = s.scenario.name;
  j["world_seed"] = s.scenario.seed;
  j["seed"] = spec.seed;
  j["device"] = s.device ? s.device->name : std::string("none");
  j["user"] = walk.user_model().name;
  j["cane"] = walk.user_model().cane.enabled;
  j["success"] = r.success;
  j["outcome"] = r.outcome;
  j["duration_s"] = r.duration_s;
  j["path_length_m"] = r.path_length_m;
  j["nominal_path_m"] = s.nominal->length();
  j["mean_speed_mps"] = r.mean_speed_mps;
  j["goal_distance_m"] = r.goal_distance_m;
  if (s.needs_facing) j["faced_landmark"] = r.faced_landmark;
  if (s.reach) j["reach"] = reach_summary(*s.reach, s.with_device, walk.end_s());
  j["experimenter_corrections"] = r.experimenter_corrections;
  j["max_off_route_m"] = r.max_off_route_m;
  j["contacts"] = contacts_summary(r);
  j["guidance_into_obstacle"] = into_obstacle_summary(r.into_obstacle);
  j["user_counts"] = user_counts_summary(r.user, walk.preferred_speed());
  const TrialDeviceCounts n = carried ? carried->counts() : TrialDeviceCounts{};
  j["time"] = {{"wall_s", r.wall_s}, {"person_and_contacts_s", walk.person_s()}, {"sensors_s", n.sensor_s},
               {"estimator_s", n.estimator_s}, {"device_s", n.device_s}, {"frames", n.frames},
               {"gps_fixes", n.gps_fixes}, {"mag_samples", n.mag_samples}};
  if (carried) {
    j["estimator"] = carried->estimator_summary();
    j["device_run"] = device_summary;
  }
  return j;
}

/// The trial's configuration: the spec's scenario and seeds over its keys.
Config trial_config(const TrialSpec& spec) {
  Config config = spec.config;
  config.apply_override("scenario=" + spec.scenario);
  config.apply_override(fmt::format("simulation.world_seed={}", spec.world_seed));
  config.apply_override(fmt::format("seed={}", spec.seed));
  return config;
}

}  // namespace

TrialResult run_trial(const TrialSpec& spec, const fs::path& out) {
  const auto wall0 = Clock::now();
  Config config = trial_config(spec);
  const ConfigReads reads(config);  // config.yaml: the given keys and the defaults the trial used
  TrialSetup s;
  configure(s, config, spec);

  fs::create_directories(out);
  write_simulation_yaml(out / "simulation.yaml", s.scenario.name, s.scenario_options);
  // The object's tag for the hand-target stage, as a simulated recording has it.
  if (s.reach_task) simulation::write_scenario_targets(s.scenario, out / io::kTargetsCsv);

  // The device the person carries (trial_device.hpp); its cues reach the person after their
  // reaction delay (cue_perception.hpp).
  std::deque<simulation::Instruction> felt;
  double trial_clock_s = 0;
  std::optional<TrialDevice> carried;
  if (s.device) {
    TrialDeviceOptions options;
    options.render_camera = s.render_camera;
    options.camera_rate_hz = s.camera_rate;
    options.save_recording = s.save_recording;
    options.cue_sink = [&felt, &trial_clock_s](const interaction::CueEvent& ev) {
      const double t_s = ns_to_seconds(ev.t - simulation::kSimulationEpoch);
      if (auto i = perceive_cue(ev, std::max(t_s, trial_clock_s))) felt.push_back(*i);
    };
    carried.emplace(*s.device, config, s.scenario, s.sim, *s.nominal, out, options);
  }
  reject_unknown_trial_keys(config, s);
  {
    std::ofstream(out / "config.yaml") << config.dump(reads.defaults());
  }

  // Run: the person and the device, one IMU tick at a time.
  TrialWalk walk(s, config, spec.seed, out);
  for (Timestamp t = walk.begin();; t += walk.imu_dt()) {
    trial_clock_s = ns_to_seconds(t);
    const simulation::KinematicState state = walk.move(t, felt, carried ? &*carried : nullptr);
    if (carried) carried->step(state, t);
    if (walk.ended(trial_clock_s, state)) break;
  }
  const nlohmann::ordered_json device_summary = carried ? carried->finish() : nlohmann::ordered_json();

  TrialResult r = walk.result(seconds_since(wall0));
  r.summary = trial_summary(spec, s, walk, r, carried ? &*carried : nullptr, device_summary);
  std::ofstream(out / "summary.json") << r.summary.dump(2) << "\n";
  return r;
}

}  // namespace navaid::experiments
