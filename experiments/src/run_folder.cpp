#include "navaid/experiments/run_folder.hpp"

#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/io/text_file.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::experiments {
namespace {

constexpr std::array<std::string_view, 34> kColumns{
    "t_ns",    "px",      "py",      "pz",      "qw",      "qx",      "qy",      "qz",      "vx",
    "vy",      "vz",      "bgx",     "bgy",     "bgz",     "bax",     "bay",     "baz",     "mode",
    "cov_pxx", "cov_pxy", "cov_pxz", "cov_pyy", "cov_pyz", "cov_pzz", "cov_rxx", "cov_rxy", "cov_rxz",
    "cov_ryy", "cov_ryz", "cov_rzz", "enu_yaw", "enu_x",   "enu_y",   "enu_z"};

// Upper triangle (xx xy xz yy yz zz) from column `first` into the symmetric 3x3 block at `base`.
void read_block(const io::TextFile& file, const std::vector<std::string_view>& f, std::size_t first, int base,
                Mat15& P) {
  std::size_t c = first;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j, ++c) P(base + i, base + j) = P(base + j, base + i) = io::parse_double(file, f[c], kColumns[c]);
}

}  // namespace

std::vector<StateEstimate> read_estimates_csv(const std::filesystem::path& path) {
  io::TextFile file(path);
  std::string line;
  if (!file.next(line)) file.fail("empty file, expected the header " + std::string(kColumns[0]) + ",...");
  const auto header = io::split_fields(line, ',');
  for (std::size_t c = 0; c < 30; ++c)
    if (c >= header.size() || header[c] != kColumns[c])
      file.fail("header column " + std::to_string(c + 1) + " must be '" + std::string(kColumns[c]) +
                "' (an estimates.csv written by navaid run)");
  std::vector<StateEstimate> out;
  while (file.next(line)) {
    if (io::is_blank_or_comment(line)) continue;
    const auto f = io::split_fields(line, ',');
    io::require_field_count(file, f, 30, true);
    StateEstimate s;
    s.t = io::parse_nanoseconds_field(file, f[0], kColumns[0]);
    io::require_increasing(file, out.empty() ? 0 : out.back().t, s.t, !out.empty());
    double v[17];
    for (std::size_t c = 1; c < 17; ++c) v[c] = io::parse_double(file, f[c], kColumns[c]);
    const Quat q(v[4], v[5], v[6], v[7]);
    io::require_unit_quaternion(file, q, "qw qx qy qz");
    s.T_W_B = SE3(q.normalized(), Vec3(v[1], v[2], v[3]));
    s.v_W = Vec3(v[8], v[9], v[10]);
    s.b_g = Vec3(v[11], v[12], v[13]);
    s.b_a = Vec3(v[14], v[15], v[16]);
    const auto mode = estimator_mode_from_string(f[17]);
    if (!mode) file.fail("unknown mode '" + std::string(f[17]) + "'");
    s.mode = *mode;
    s.covariance = Mat15::Identity();
    read_block(file, f, 18, 3, s.covariance);  // position first in the file, rotation next
    read_block(file, f, 24, 0, s.covariance);
    out.push_back(std::move(s));
  }
  return out;
}

std::filesystem::path run_recording(const std::filesystem::path& run_folder) {
  const std::filesystem::path file = run_folder / "summary.json";
  std::ifstream in(file);
  if (!in) throw IoError(file.string(), "cannot read (not a navaid run folder?)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw IoError(file.string(), std::string("is not valid JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("recording") || !j["recording"].is_string())
    throw IoError(file.string(), "has no \"recording\" string (the recording the run was made on)");
  return j["recording"].get<std::string>();
}

}  // namespace navaid::experiments
