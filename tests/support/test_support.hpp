#pragma once
// Shared helpers for the test suites: where the real data is, scratch folders, file writing,
// expected exceptions.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "navaid/core/calibration.hpp"

namespace navaid::testing {

/// ../shared/data beside the clone. When it is absent, tests that need it are skipped on a
/// developer machine and fail in CI (CI=true), where the data must be present.
std::filesystem::path shared_data_dir();
/// True when shared_data_dir() exists; otherwise records a skip (or failure in CI).
bool have_shared_data();

/// A fresh, empty folder under the build's temp area, removed when the object dies.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& child) const { return path_ / child; }

 private:
  std::filesystem::path path_;
};

void write_text(const std::filesystem::path& file, const std::string& content);
std::string read_text(const std::filesystem::path& file);

/// IMU noise of the EuRoC MAV's ADIS16448 (Kalibr units) at `rate_hz`: the reference IMU of the
/// simulator and estimator tests.
ImuCalibration euroc_imu_calibration(double rate_hz = 200.0);

/// Every regular file under `root`, byte for byte, keyed by its relative path.
std::map<std::string, std::string> folder_contents(const std::filesystem::path& root);

/// Exit status and output of one run of the navaid program.
struct CliRun {
  int status = -1;
  std::string output;  ///< stdout, plus stderr when asked for
};
/// Runs `navaid <args>` (args are passed to the shell as written).
CliRun navaid_cli(const std::string& args, bool with_stderr = true);

/// A folder of inputs that all test processes of a build share (a simulated walk, a run of it).
/// CTest runs every test in a process of its own, so a suite's SetUpTestSuite would make its inputs
/// again for each test: shared_fixture makes them once per build of the navaid program. `make`
/// fills the folder under a file lock; later callers with the same `name` and `recipe` (the
/// commands `make` runs, so that a changed recipe is made anew) wait for it and read what it made.
/// Throws std::runtime_error, naming the fixture, when `make` fails; the next caller tries again.
/// Tests read the folder and never write into it: a test that edits an input copies it first.
std::filesystem::path shared_fixture(const std::string& name, const std::string& recipe,
                                     const std::function<void(const std::filesystem::path&)>& make);

/// A shared_fixture made by navaid commands, run in order; "{dir}" in a command stands for the
/// fixture's folder (quoted). A command that fails throws with its output.
std::filesystem::path shared_cli_fixture(const std::string& name, const std::vector<std::string>& commands);

/// Runs `f` and returns the E it throws. When it throws nothing, records a test failure that
/// names `context` and returns nullopt; an exception of another type propagates.
template <class E, class F>
std::optional<E> expect_throw(F&& f, const std::string& context = {}) {
  try {
    std::forward<F>(f)();
  } catch (const E& e) {
    return e;
  }
  ADD_FAILURE() << "expected an exception, none was thrown" << (context.empty() ? "" : ": ") << context;
  return std::nullopt;
}

/// The message of the E that `f` throws; empty, with a test failure, when it throws none.
template <class E, class F>
std::string error_message(F&& f, const std::string& context = {}) {
  const std::optional<E> e = expect_throw<E>(std::forward<F>(f), context);
  return e ? std::string(e->what()) : std::string();
}

}  // namespace navaid::testing

/// Use at the top of a test that reads ../shared/data.
#define NAVAID_REQUIRE_SHARED_DATA()                                              \
  do {                                                                            \
    if (!::navaid::testing::have_shared_data()) {                                 \
      if (std::getenv("CI")) FAIL() << "../shared/data is missing in CI";         \
      GTEST_SKIP() << "../shared/data not present beside the clone";              \
    }                                                                             \
  } while (0)
