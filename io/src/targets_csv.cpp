#include "navaid/io/targets_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "navaid/core/errors.hpp"
#include "navaid/io/text_file.hpp"

namespace navaid::io {
namespace fs = std::filesystem;

namespace {

constexpr const char* kHeader = "name,class,family,tag_id,tag_size_m,cx,cy,cz,hx,hy,hz,tx,ty,tz,qw,qx,qy,qz";
constexpr std::size_t kColumns = 18;

std::string shortest(double v) {
  if (!std::isfinite(v)) throw std::invalid_argument("targets.csv: a value is not finite");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

void write_targets_csv(const fs::path& path, const std::vector<TargetGroundTruth>& targets) {
  std::string text = std::string(kHeader) + "\n";
  for (const TargetGroundTruth& t : targets) {
    if (t.name.empty() || t.name.find_first_of(",\n\r") != std::string::npos)
      throw std::invalid_argument("targets.csv: target name '" + t.name + "' must be non-empty without commas or line breaks");
    if (t.tag_id < 0) throw std::invalid_argument("targets.csv: negative tag id for '" + t.name + "'");
    text += t.name + "," + std::string(semantic_class_name(t.semantic)) + "," + t.tag_family + "," +
            std::to_string(t.tag_id) + "," + shortest(t.tag_size_m);
    for (int i = 0; i < 3; ++i) text += "," + shortest(t.center_W[i]);
    for (int i = 0; i < 3; ++i) text += "," + shortest(t.half_extents[i]);
    for (int i = 0; i < 3; ++i) text += "," + shortest(t.T_W_tag.t[i]);
    const Quat q = t.T_W_tag.q;
    for (double v : {q.w(), q.x(), q.y(), q.z()}) text += "," + shortest(v);
    text += "\n";
  }
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw IoError(path.string(), "cannot write the file");
}

std::vector<TargetGroundTruth> read_targets_csv(const fs::path& path) {
  TextFile file(path);
  std::string line;
  bool header = false;
  std::vector<TargetGroundTruth> targets;
  while (file.next(line)) {
    if (is_blank_or_comment(line)) continue;
    if (!header) {
      if (trim(line) != kHeader) file.fail("expected the header '" + std::string(kHeader) + "'");
      header = true;
      continue;
    }
    const auto f = split_fields(line, ',');
    require_field_count(file, f, kColumns);
    TargetGroundTruth t;
    t.name = std::string(f[0]);
    if (t.name.empty()) file.fail("column 'name' is empty");
    try {
      t.semantic = semantic_class_from_name(f[1]);
    } catch (const ConfigError&) {
      file.fail("column 'class': unknown semantic class '" + std::string(f[1]) + "'");
    }
    t.tag_family = std::string(f[2]);
    const long long id = parse_integer(file, f[3], "tag_id");
    if (id < 0 || id > 1000000) file.fail("column 'tag_id': " + std::string(f[3]) + " is not a tag id (0 .. 1000000)");
    t.tag_id = static_cast<int>(id);
    t.tag_size_m = parse_double(file, f[4], "tag_size_m");
    if (!(t.tag_size_m > 0.0)) file.fail("column 'tag_size_m': " + std::string(f[4]) + " must be positive");
    static const char* names[] = {"cx", "cy", "cz", "hx", "hy", "hz", "tx", "ty", "tz", "qw", "qx", "qy", "qz"};
    double v[13];
    for (int i = 0; i < 13; ++i) v[i] = parse_double(file, f[5 + i], names[i]);
    t.center_W = Vec3(v[0], v[1], v[2]);
    t.half_extents = Vec3(v[3], v[4], v[5]);
    Quat q(v[9], v[10], v[11], v[12]);
    if (std::abs(q.norm() - 1.0) > 1e-3) file.fail("columns 'qw'..'qz': the quaternion is not unit (norm " + std::to_string(q.norm()) + ")");
    t.T_W_tag = SE3(q.normalized(), Vec3(v[6], v[7], v[8]));
    targets.push_back(t);
  }
  if (!header) file.fail("empty file: expected the header '" + std::string(kHeader) + "'");
  return targets;
}

}  // namespace navaid::io
