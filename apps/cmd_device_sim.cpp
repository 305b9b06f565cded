// navaid device-sim: the vibration controller's firmware (interaction/firmware/navaid_link.c) run
// on this machine behind a pseudo-terminal, so that the device link can be tried without a belt,
// hand unit, rumble remotes or wheel (docs/device-protocol.md). --link makes a symlink to the pty
// for the host to open; --attach uses an existing tty instead (one end of a socat pair). Prints
// the actuator outputs and counters every --status-s seconds until Ctrl-C or --duration.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/actuator_pattern.hpp"
#include "navaid/interaction/device_adapter.hpp"
#include "navaid_link_sim.hpp"

namespace navaid::cli {

namespace {

struct DeviceSimArgs {
  std::string device;
  std::string link;
  std::string attach;
  double duration_s = 0.0;
  double status_s = 1.0;
};

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

std::string status_line(const firmware_sim::ControllerSnapshot& s, int actuators) {
  std::string out;
  for (int i = 0; i < actuators; ++i) out += fmt::format("{}{:5}", i == 0 ? "" : " ", s.outputs[i]);
  return fmt::format("out [{}]  link {}  patterns {}  all_off {}  heartbeats {}  acks {}  naks {}  crc_errors {}  "
                     "hold_expiries {}  link_timeouts {}",
                     out, s.link_alive ? "up" : "down", s.device.patterns_applied, s.device.all_off_commands,
                     s.device.heartbeats, s.device.acks_sent, s.device.naks_sent, s.decoder.crc_errors,
                     s.device.hold_expiries, s.device.link_timeouts);
}

void run(const DeviceSimArgs& a) {
  const std::optional<interaction::DeviceKind> kind = interaction::device_kind_from_string(a.device);
  if (!kind) throw UsageError(fmt::format("--device must be belt, hand, rumble or wheel, not '{}'", a.device));
  if (a.link.empty() == a.attach.empty()) throw UsageError("give exactly one of --link PATH or --attach TTY");
  // The actuator count the host's adapter drives.
  const int actuators = interaction::make_device_adapter(*kind, Config())->actuator_count();
  const auto code = static_cast<std::uint8_t>(*kind);
  const auto n = static_cast<std::uint8_t>(actuators);
  std::unique_ptr<firmware_sim::SimulatedController> sim;
  try {
    if (a.attach.empty()) {
      sim = std::make_unique<firmware_sim::SimulatedController>(code, n, a.link);
    } else {
      sim = std::make_unique<firmware_sim::SimulatedController>(code, n,
                                                                firmware_sim::SimulatedController::AttachTo{a.attach});
    }
  } catch (const std::runtime_error& e) {
    throw IoError(a.attach.empty() ? a.link : a.attach, e.what());
  }
  std::cout << fmt::format("{} controller ({} actuators) on {}{}; Ctrl-C stops\n", interaction::to_string(*kind),
                           actuators, sim->slave_path(), a.link.empty() ? "" : ", host opens " + a.link)
            << std::flush;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const auto start = std::chrono::steady_clock::now();
  auto next_status = start;
  while (!g_stop) {
    const auto now = std::chrono::steady_clock::now();
    if (a.duration_s > 0 && std::chrono::duration<double>(now - start).count() >= a.duration_s) break;
    if (a.status_s > 0 && now >= next_status) {
      std::cout << status_line(sim->snapshot(), actuators) << "\n" << std::flush;
      next_status = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(a.status_s));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const firmware_sim::ControllerSnapshot last = sim->snapshot();
  sim->stop();
  std::cout << "final: " << status_line(last, actuators) << "\n";
}

}  // namespace

void add_device_sim_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("device-sim",
                                 "Run the vibration controller's firmware behind a pseudo-terminal (device link "
                                 "without hardware, docs/device-protocol.md)");
  auto a = std::make_shared<DeviceSimArgs>();
  cmd->add_option("--device", a->device, "belt | hand | rumble | wheel")->required();
  cmd->add_option("--link", a->link, "Symlink to create for the pty; the host opens this path");
  cmd->add_option("--attach", a->attach, "Use this existing tty instead of a new pty (e.g. a socat end)");
  cmd->add_option("--duration", a->duration_s, "Stop after this many seconds (0: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e9));
  cmd->add_option("--status-s", a->status_s, "Print outputs and counters this often (0: never)")
      ->check(CLI::Range(0.0, 3600.0));
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
