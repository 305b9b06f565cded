// The corrupt-recording matrix (docs/robustness.md): kinds of damage applied to real and simulated
// recordings, each run through the navaid command that consumes the damaged data. Every kind must
// end in a clear error naming the file (and the line, for text files) or in a counted, documented
// skip; never a crash and never a silently accepted result.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "navaid/core/image.hpp"
#include "navaid/io/image_io.hpp"
#include "recording_edits.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::CliRun;
using navaid::testing::edit_line;
using navaid::testing::join_csv;
using navaid::testing::lines_of;
using navaid::testing::split_csv;
using navaid::testing::write_lines;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

namespace {

enum class Base { kSimFeatures, kSimImages, kEuroc, kNmea, kTumTrajectory };
enum class Outcome { kError, kCountedSkip, kAccepted };

struct Damage {
  std::string kind;
  Base base;
  std::string command;  ///< "info", "run" or "map": the step that consumes the damaged data
  std::function<void(const fs::path&)> apply;
  Outcome outcome;
  std::vector<std::string> mentions;  ///< what the output must say (file:line, key, count)
};

// gtest prints a parameter with its kind, not as bytes.
void PrintTo(const Damage& d, std::ostream* os) { *os << d.kind; }

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

// ---- Base recordings, made once per test process --------------------------------------------

const fs::path& base_root() {
  static const ScratchDir root("corrupt-recordings-base");
  return root.path();
}

fs::path simulated(const std::string& name, const std::string& args) {
  const fs::path out = base_root() / name;
  if (!fs::exists(out / "recording.yaml")) {
    const CliRun run = navaid_cli("simulate " + args + " --seed 1 --threads 1 --out " + quote(out));
    if (run.status != 0) throw std::runtime_error("cannot simulate the base recording: " + run.output);
  }
  return out;
}

/// The real EuRoC V1_01 images are linked, not copied (34 MB); the text files are copied.
fs::path euroc_base() {
  const fs::path out = base_root() / "euroc-V1_01";
  if (fs::exists(out)) return out;
  const fs::path real = navaid::testing::shared_data_dir() / "euroc-V1_01-micro" / "mav0";
  for (const char* sensor : {"cam0", "imu0", "state_groundtruth_estimate0"}) {
    fs::create_directories(out / "mav0" / sensor);
    for (const char* file : {"data.csv", "sensor.yaml"})
      if (fs::exists(real / sensor / file)) fs::copy_file(real / sensor / file, out / "mav0" / sensor / file);
  }
  fs::create_directory_symlink(real / "cam0" / "data", out / "mav0" / "cam0" / "data");
  return out;
}

fs::path base_path(Base b) {
  switch (b) {
    case Base::kSimFeatures:
      return simulated("route1-features", "--scenario route1 --set simulation.mode=features --set duration=1");
    case Base::kSimImages:
      return simulated("lab-walk-1-images",
                       "--scenario lab-walk-1 --mount hand --set duration=0.2 --set sensor.camera.resolution=[32,24]");
    case Base::kEuroc: return euroc_base();
    case Base::kNmea: return navaid::testing::shared_data_dir() / "gpsd-nmea" / "bu353s4.log";
    case Base::kTumTrajectory: return navaid::testing::shared_data_dir() / "evo-trajectories" / "V101_gt.txt";
  }
  return {};
}

// ---- Editing helpers ------------------------------------------------------------------------

void set_field(const fs::path& file, std::size_t line, std::size_t column, const std::string& value) {
  edit_line(file, line, [&](std::string& l) {
    auto f = split_csv(l);
    f.at(column) = value;
    l = join_csv(f);
  });
}

/// Rewrites every CSV time stamp from line `from` on by `shift_ns`.
void shift_times(const fs::path& file, std::size_t from, long long shift_ns) {
  auto lines = lines_of(file);
  for (std::size_t i = from - 1; i < lines.size(); ++i) {
    auto f = split_csv(lines[i]);
    f[0] = std::to_string(std::stoll(f[0]) + shift_ns);
    lines[i] = join_csv(f);
  }
  write_lines(file, lines);
}

/// The image named in column `column` of frames.csv line `line` (relative path).
std::string frame_image(const fs::path& rec, std::size_t line, std::size_t column) {
  return split_csv(lines_of(rec / "frames.csv").at(line - 1)).at(column);
}

void truncate_file(const fs::path& file, std::size_t keep) {
  const std::string bytes = read_text(file);
  write_text(file, bytes.substr(0, std::min(keep, bytes.size())));
}

void replace_all(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = read_text(file);
  const std::size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error(file.string() + ": no '" + from + "' to replace");
  for (std::size_t p = at; p != std::string::npos; p = text.find(from, p + to.size())) text.replace(p, from.size(), to);
  write_text(file, text);
}

// frames.csv columns: t_ns,camera,index,intensity,depth,labels,confidence
constexpr std::size_t kIntensity = 3, kDepth = 4, kLabels = 5;

// ---- The matrix -----------------------------------------------------------------------------

std::vector<Damage> matrix() {
  using O = Outcome;
  const Base F = Base::kSimFeatures, I = Base::kSimImages;
  std::vector<Damage> m = {
      {"TruncatedMidWrite", F, "info", [](const fs::path& r) { truncate_file(r / "imu.csv", read_text(r / "imu.csv").size() - 40); },
       O::kError, {"imu.csv:202:", "expected 7 fields"}},
      {"MissingColumn", F, "info", [](const fs::path& r) { edit_line(r / "imu.csv", 5, [](std::string& l) { l = l.substr(0, l.rfind(',')); }); },
       O::kError, {"imu.csv:5:", "expected 7 fields, found 6"}},
      {"ExtraColumn", F, "info", [](const fs::path& r) { edit_line(r / "imu.csv", 5, [](std::string& l) { l += ",1.0"; }); },
       O::kError, {"imu.csv:5:", "found 8"}},
      {"NonNumericField", F, "info", [](const fs::path& r) { set_field(r / "imu.csv", 5, 1, "abc"); },
       O::kError, {"imu.csv:5:", "'gx'", "not a number"}},
      {"NanField", F, "info", [](const fs::path& r) { set_field(r / "mag.csv", 4, 2, "nan"); },
       O::kError, {"mag.csv:4:", "not a finite number"}},
      {"InfField", F, "info", [](const fs::path& r) { set_field(r / "gps.csv", 3, 1, "inf"); },
       O::kError, {"gps.csv:3:", "'lat'", "not a finite number"}},
      {"OutOfRangeLatitude", F, "info", [](const fs::path& r) { set_field(r / "gps.csv", 2, 1, "130.5"); },
       O::kError, {"gps.csv:2:", "outside [-90, 90]"}},
      {"DuplicateTimestamp", F, "info",
       [](const fs::path& r) { auto l = lines_of(r / "imu.csv"); l.insert(l.begin() + 5, l[4]); write_lines(r / "imu.csv", l); },
       O::kError, {"imu.csv:6:", "duplicate timestamp"}},
      {"DecreasingTimestamp", F, "info",
       [](const fs::path& r) { auto l = lines_of(r / "imu.csv"); std::swap(l[4], l[5]); write_lines(r / "imu.csv", l); },
       O::kError, {"imu.csv:6:", "decreasing timestamp"}},
      {"JumpingTimestamp", F, "info", [](const fs::path& r) { shift_times(r / "imu.csv", 101, 3600'000'000'000LL); },
       O::kCountedSkip, {"warnings     1", "imu: gap of 3600.01 s"}},
      {"FloatTimestamp", F, "info", [](const fs::path& r) { set_field(r / "imu.csv", 7, 0, "1.70407e+18"); },
       O::kError, {"imu.csv:7:", "not an integer time in nanoseconds"}},
      {"HeaderColumnsSwapped", F, "info", [](const fs::path& r) { edit_line(r / "imu.csv", 1, [](std::string& l) { l = "t_ns,gy,gx,gz,ax,ay,az"; }); },
       O::kError, {"imu.csv:1:", "header must be"}},
      {"ByteOrderMark", F, "info", [](const fs::path& r) { write_text(r / "imu.csv", "\xEF\xBB\xBF" + read_text(r / "imu.csv")); },
       O::kAccepted, {"imu               201", "warnings     0"}},
      {"EmptyFile", F, "info", [](const fs::path& r) { write_text(r / "groundtruth.csv", ""); },
       O::kError, {"groundtruth.csv", "missing header line"}},
      {"BinaryGarbage", F, "info",
       [](const fs::path& r) { std::string g; for (int i = 0; i < 3000; ++i) g += static_cast<char>((i * 131 + 7) % 256); write_text(r / "imu.csv", g); },
       O::kError, {"imu.csv:1:", "header must be"}},
      {"NonUnitQuaternion", F, "info", [](const fs::path& r) { set_field(r / "groundtruth.csv", 4, 4, "0.5"); },
       O::kError, {"groundtruth.csv:4:", "quaternion"}},
      {"IndexNamesMissingFile", F, "info", [](const fs::path& r) { fs::remove(r / "mag.csv"); },
       O::kError, {"mag.csv", "recording.yaml lists sensor 'mag'"}},
      {"IndexNamesExtraSensor", F, "info", [](const fs::path& r) { replace_all(r / "recording.yaml", "landmarks]", "landmarks, frames]"); },
       O::kError, {"frames.csv", "recording.yaml lists sensor 'frames'"}},
      {"UnsupportedVersion", F, "info", [](const fs::path& r) { replace_all(r / "recording.yaml", "version: 2", "version: 99"); },
       O::kError, {"recording.yaml", "'version'", "99"}},
      {"CalibrationKeyMissing", I, "info",
       [](const fs::path& r) { replace_all(r / "calibration.yaml", "    intrinsics: [23, 23, 15.5, 11.5]\n", ""); },
       O::kError, {"calibration.yaml", "cameras[0].intrinsics", "missing"}},
      {"CalibrationInconsistent", I, "info",
       [](const fs::path& r) { replace_all(r / "calibration.yaml", "q_wxyz: [-0.45451947767204365", "q_wxyz: [-0.9"); },
       O::kError, {"calibration.yaml", "T_B_C"}},
      {"CrlfLineEndings", F, "info", [](const fs::path& r) { replace_all(r / "imu.csv", "\n", "\r\n"); },
       O::kAccepted, {"imu               201", "warnings     0"}},
      {"MissingImage", I, "info", [](const fs::path& r) { fs::remove(r / frame_image(r, 5, kIntensity)); },
       O::kError, {"frames.csv:5:", "does not exist"}},
      {"ImagePathEscapes", I, "info", [](const fs::path& r) { set_field(r / "frames.csv", 3, kIntensity, "../../etc/passwd"); },
       O::kError, {"frames.csv:3:", "must stay inside the recording folder"}},
      {"ImagePathAbsolute", I, "info", [](const fs::path& r) { set_field(r / "frames.csv", 3, kDepth, "/etc/passwd"); },
       O::kError, {"frames.csv:3:", "must be a path relative to the recording folder"}},
      {"UnreadablePng", I, "run", [](const fs::path& r) { truncate_file(r / frame_image(r, 5, kIntensity), 100); },
       O::kError, {"cannot decode image"}},
      {"IntensityPng16Bit", I, "run",
       [](const fs::path& r) { navaid::io::write_png((r / frame_image(r, 4, kIntensity)).string(), navaid::ImageU16(32, 24, 1, 2000)); },
       O::kError, {"intensity image must have 8 bits per channel"}},
      {"WrongSizeDepth", I, "map",
       [](const fs::path& r) { navaid::io::write_png((r / frame_image(r, 4, kDepth)).string(), navaid::ImageU16(16, 12, 1, 1500)); },
       O::kError, {"depth/cam0_", "depth is 16x12", "32x24"}},
      {"DepthInMetres", I, "map",
       [](const fs::path& r) { navaid::io::write_png((r / frame_image(r, 4, kDepth)).string(), navaid::ImageU16(32, 24, 1, 3)); },
       O::kError, {"every valid depth value is below"}},
      {"Depth8Bit", I, "map",
       [](const fs::path& r) { navaid::io::write_png((r / frame_image(r, 4, kDepth)).string(), navaid::ImageU8(32, 24, 1, 90)); },
       O::kError, {"depth image must be a 16-bit single-channel PNG"}},
      {"LabelsOutOfRange", I, "map",
       [](const fs::path& r) { navaid::io::write_png((r / frame_image(r, 4, kLabels)).string(), navaid::ImageU8(32, 24, 1, 200)); },
       O::kError, {"labels/cam0_", "label 200", "is not a class id"}},
      {"EurocTruncatedMidWrite", Base::kEuroc, "info",
       [](const fs::path& r) { auto f = r / "mav0/imu0/data.csv"; truncate_file(f, read_text(f).size() - 25); },
       O::kError, {"imu0/data.csv:", "fields"}},
      {"EurocMissingImage", Base::kEuroc, "info",
       [](const fs::path& r) { edit_line(r / "mav0/cam0/data.csv", 4, [](std::string& l) { l = split_csv(l)[0] + ",0.png"; }); },
       O::kError, {"cam0/data.csv:4:", "does not exist"}},
      {"EurocCalibrationKeyMissing", Base::kEuroc, "info",
       [](const fs::path& r) {
         auto l = lines_of(r / "mav0/cam0/sensor.yaml");
         l.erase(std::remove_if(l.begin(), l.end(), [](const std::string& s) { return s.rfind("intrinsics", 0) == 0; }),
                 l.end());
         write_lines(r / "mav0/cam0/sensor.yaml", l);
       },
       O::kError, {"cam0/sensor.yaml", "intrinsics"}},
      {"NmeaBadChecksumAndGarbage", Base::kNmea, "info",
       [](const fs::path& r) {
         edit_line(r, 10, [](std::string& l) { l = l.substr(0, l.rfind('*')) + "*00"; });
         edit_line(r, 20, [](std::string& l) { l = std::string("\x01\x02\xff") + l; });
       },
       O::kCountedSkip, {"warnings     2", "line 10: bad checksum", "line 20: garbage before a sentence"}},
      {"TumTrajectoryNonUnitQuaternion", Base::kTumTrajectory, "info",
       [](const fs::path& r) { edit_line(r, 3, [](std::string& l) { l = l.substr(0, l.rfind(' ')) + " 0.9"; }); },
       O::kError, {"V101_gt.txt:3:", "quaternion"}},
  };
  return m;
}

class CorruptRecording : public ::testing::TestWithParam<Damage> {};

TEST_P(CorruptRecording, EndsInAClearErrorOrACountedSkip) {
  NAVAID_REQUIRE_SHARED_DATA();
  const Damage& d = GetParam();
  const ScratchDir dir("corrupt-" + d.kind);
  const fs::path base = base_path(d.base);
  const fs::path damaged = dir / base.filename().string();
  fs::copy(base, damaged, fs::copy_options::recursive | fs::copy_options::copy_symlinks);
  d.apply(damaged);

  std::string args = d.command + " ";
  if (d.command == "info") args += quote(damaged);
  if (d.command == "run") args += "--recording " + quote(damaged) + " --out " + quote(dir / "run") + " --no-plot";
  if (d.command == "map")
    args += "--recording " + quote(damaged) + " --poses groundtruth --out " + quote(dir / "map") + " --no-quality";
  const CliRun run = navaid_cli(args);
  SCOPED_TRACE("navaid " + args + "\n" + run.output);
  if (d.outcome == Outcome::kError) {
    EXPECT_EQ(run.status, 2) << "a bad input must end in navaid's error exit (2), not a crash or success";
    EXPECT_NE(run.output.find("navaid: error: "), std::string::npos);
  } else {
    EXPECT_EQ(run.status, 0);
  }
  for (const std::string& m : d.mentions) EXPECT_NE(run.output.find(m), std::string::npos) << "missing: " << m;
}

INSTANTIATE_TEST_SUITE_P(Matrix, CorruptRecording, ::testing::ValuesIn(matrix()),
                         [](const ::testing::TestParamInfo<Damage>& p) { return p.param.kind; });

TEST(CorruptRecordingMatrix, HasAtLeastTwentyKindsOnRealAndSimulatedRecordings) {
  const auto m = matrix();
  EXPECT_GE(m.size(), 20u);
  std::map<Base, int> per_base;
  for (const auto& d : m) ++per_base[d.base];
  EXPECT_EQ(per_base.size(), 5u) << "simulated features and images, real EuRoC, NMEA and TUM files";
}

}  // namespace
