// A device app on navaid's runtime: a recording's sensor events are fed to the estimator and the
// device at the pace they were recorded, and the cues and speech print as the device makes them.
//   device_app RECORDING DEVICE [--speed S] [--set key=value ...]   (S: x real time, 0 = as fast as it goes)
// DEVICE is a preset (smart-cane, augmented-cane, w-roma, elabrador). The mission comes from the
// configuration: device.goal_start_frame_m (smart-cane), device.tag_id (w-roma), device.route.osm
// and device.route.to (elabrador, starting at the first GPS fix).
#include <cstdio>
#include <exception>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <navaid/core/errors.hpp>
#include <navaid/estimation/frontend/image_feature_source.hpp>
#include <navaid/estimation/sliding_window_estimator.hpp>
#include <navaid/io/image_io.hpp>
#include <navaid/io/open_input.hpp>
#include <navaid/runtime/device.hpp>
#include <navaid/runtime/estimator_pipeline.hpp>

using namespace navaid;

namespace {

void load_images(RgbdFrame& frame) {
  frame.intensity = io::read_intensity_image(frame.intensity_path);
  if (!frame.depth_path.empty()) frame.depth = io::read_depth_png(frame.depth_path, frame.depth_png_scale_m);
}

// What the user would tell an eLabrador: the streets and where to go. The other devices' missions
// are keys of their configuration.
runtime::DeviceMission mission_of(const runtime::DeviceSpec& spec, const io::Recording& recording) {
  runtime::DeviceMission mission;
  if (spec.guidance != runtime::GuidanceKind::kRoute) return mission;
  if (spec.route_osm.empty() || !spec.route_to || recording.gps.empty() || !recording.origin)
    throw UsageError("a route needs --set device.route.osm=FILE --set device.route.to=[LAT,LON] and GPS fixes");
  const GpsFix& start = recording.gps.front();
  mission.route = runtime::RouteMission{planning::load_osm_foot_graph(spec.route_osm), spec.route_osm.string(),
                                        {start.latitude_deg, start.longitude_deg},
                                        {spec.route_to->first, spec.route_to->second}, std::nullopt, *recording.origin};
  return mission;
}

void print_cue(const interaction::CueEvent& e, Timestamp t0) {
  if (e.outcome != interaction::CueOutcome::kSent && e.outcome != interaction::CueOutcome::kSpoken) return;
  std::string what = std::string(interaction::to_string(e.cue.kind));
  if (e.pattern)
    for (const auto& c : e.pattern->commands) what += " " + std::to_string(c.actuator) + ":" + std::to_string(c.level);
  if (!e.text.empty()) what += " \"" + e.text + "\"";
  std::printf("%8.2f s  %s\n", ns_to_seconds(e.t - t0), what.c_str());
  std::fflush(stdout);
}

int run(int argc, char** argv) {
  if (argc < 3) throw UsageError("usage: device_app RECORDING DEVICE [--speed S] [--set key=value ...]");
  std::vector<std::string> overrides;
  runtime::RealtimeOptions pace;
  pace.speed = 1.0;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--set") overrides.push_back(argv[i + 1]);
    else if (flag == "--speed") pace.speed = std::stod(argv[i + 1]);
    else throw UsageError("unknown option " + flag);
  }
  runtime::validate(pace);  // --speed 0: as fast as it goes, no frame dropped
  const io::Recording recording = io::read_input(argv[1]);
  if (recording.calibration.cameras.empty() || recording.imu.empty())
    throw UsageError(std::string(argv[1]) + ": a device needs a camera and an IMU");
  const Config config = Config::load(runtime::device_preset_file(argv[2]), overrides);
  const runtime::DeviceSpec spec = runtime::read_device_spec(config);
  const CameraCalibration& camera = recording.calibration.cameras.front();

  // The estimator: on the recording's features, or tracking its images with its own front end.
  estimation::SlidingWindowEstimator estimator(recording.calibration, estimation::read_estimator_config(config),
                                               camera.name, recording.origin);
  std::optional<runtime::EstimatorDriver> driver;
  if (recording.features.empty())
    driver.emplace(std::move(estimator), estimation::ImageFeatureSource(recording.calibration,
                                                                        estimation::read_frontend_config(config),
                                                                        camera.name, &load_images));
  else
    driver.emplace(std::move(estimator));

  // The device: real time (a full queue drops its oldest estimate), guidance from the newest
  // estimate carried through the IMU to each frame's arrival; cues printed as they come.
  runtime::DeviceOptions options;
  options.drop_when_full = true;
  options.predict_at_arrival = true;
  options.mapping = runtime::read_mapping_stage_options(config);
  if (recording.calibration.imu) options.imu_noise = estimation::ImuNoise::from(*recording.calibration.imu);
  const Timestamp t0 = recording.imu.front().t;
  std::mutex print_m;
  runtime::DeviceSinks sinks;
  sinks.cue = [&](const interaction::CueEvent& e) {
    std::lock_guard<std::mutex> lock(print_m);
    print_cue(e, t0);
  };
  runtime::Device device(spec, config, camera, mission_of(spec, recording), options, std::move(sinks));
  for (const RgbdFrame& f : recording.frames)
    if (f.camera == camera.name) device.add_frame(&f);

  std::size_t imu_next = 0;
  runtime::PipelineInput input{recording, camera.name, *driver, &load_images,
                               estimation::read_frontend_config(config).imu_prediction};
  input.on_record = [](const runtime::FrameRecord&) {};
  input.on_estimate = [&](const StateEstimate& e, runtime::Clock::time_point arrival) { device.on_estimate(e, arrival); };
  input.on_frame_arrival = [&](Timestamp t, runtime::Clock::time_point arrival) {
    // The IMU has delivered up to the frame's time (and the sample just after it, 5 ms later at 200 Hz).
    for (; imu_next < recording.imu.size() && (imu_next == 0 || recording.imu[imu_next - 1].t < t); ++imu_next)
      device.add_imu(recording.imu[imu_next]);
    device.on_frame_arrival(t, arrival);
  };
  std::printf("%s on %s, %s\n", spec.name.c_str(), argv[1],
              pace.speed > 0 ? (std::to_string(pace.speed) + "x real time").c_str() : "as fast as it goes");
  runtime::realtime_pipeline(input, pace);
  const runtime::DeviceResult result = device.finish();
  if (result.error) std::rethrow_exception(result.error);
  std::printf("%zu cue events; frame-to-cue latency p99 %.1f ms\n", result.events.size(),
              result.summary["latency"]["p99_ms"].get<double>());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "device_app: " << e.what() << "\n";
    return 1;
  }
}
