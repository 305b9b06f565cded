// The HPnP-vs-PnP study (pose_change_study.hpp, docs/initialization.md "HPnP vs PnP study").
#include "navaid/estimation/initialization/pose_change_study.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>
#include <unordered_map>

#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"

namespace navaid::estimation {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Ground-truth body pose at t by interpolation; nullopt outside the ground truth.
std::optional<SE3> groundtruth_at(const std::vector<GroundTruthState>& gt, Timestamp t) {
  if (gt.empty() || t < gt.front().t || t > gt.back().t) return std::nullopt;
  const auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const GroundTruthState& s, Timestamp x) { return s.t < x; });
  if (it->t == t) return it->T_W_B;
  const auto& a = *std::prev(it);
  return interpolate(a.T_W_B, it->T_W_B, static_cast<double>(t - a.t) / static_cast<double>(it->t - a.t));
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(h), v.end());
  const double hi = v[h];
  if (v.size() % 2) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<long>(h)));
}

std::string num(double v, int precision) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

}  // namespace

void validate(const PoseChangeStudyOptions& o, const std::string& source) {
  if (o.gap < 1) throw ConfigError(source, "gap", "expected an integer >= 1, found " + std::to_string(o.gap));
  if (o.stride < 1) throw ConfigError(source, "stride", "expected an integer >= 1, found " + std::to_string(o.stride));
  if (!(o.min_parallax_px >= 0.0) || !std::isfinite(o.min_parallax_px))
    throw ConfigError(source, "min_parallax_px", "expected a finite value >= 0 px");
  if (!(o.min_baseline_m >= 0.0) || !std::isfinite(o.min_baseline_m))
    throw ConfigError(source, "min_baseline_m", "expected a finite value >= 0 m");
  if (o.min_correspondences < 5)
    throw ConfigError(source, "min_correspondences",
                      "expected an integer >= 5, found " + std::to_string(o.min_correspondences));
  if (o.depth_budgets.empty()) throw ConfigError(source, "depth_budgets", "expected at least one budget");
  for (int b : o.depth_budgets)
    if (b < 1 && b != kAllDepths)
      throw ConfigError(source, "depth_budgets", "expected budgets >= 1 or 'all', found " + std::to_string(b));
  if (!(o.success_rotation_deg > 0.0) || !(o.success_translation_rel >= 0.0) || !(o.success_translation_abs_m >= 0.0))
    throw ConfigError(source, "success", "expected a rotation bound > 0 deg and translation bounds >= 0");
  validate(o.pose_change, source + ".pose_change");
}

std::vector<PoseChangeWindow> make_pose_change_windows(const PoseChangeStudySequence& seq,
                                                       const PoseChangeStudyOptions& o) {
  validate(o);
  if (seq.groundtruth.empty()) throw Error("init-study: sequence '" + seq.name + "' has no ground truth");
  const auto camera = make_camera_model(seq.camera, seq.name);
  const double focal = 0.5 * (camera->fx() + camera->fy());
  const Timestamp offset = static_cast<Timestamp>(std::llround(seq.camera.time_offset_s * 1e9));

  // Undistorted normalized coordinates and depth of every feature, by track id, per frame.
  struct Obs {
    Vec2 m;
    std::optional<double> depth;
  };
  auto normalized = [&](const FeatureFrame& f) {
    std::unordered_map<std::uint64_t, Obs> out;
    for (const auto& x : f.features) {
      const auto m = camera->undistort(camera->distorted_from_pixel(x.uv));
      if (m && m->allFinite()) out.emplace(x.track_id, Obs{*m, x.depth_m});
    }
    return out;
  };

  std::vector<PoseChangeWindow> windows;
  const std::size_t n = seq.frames.size();
  for (std::size_t i = 0; i + static_cast<std::size_t>(o.gap) < n; i += static_cast<std::size_t>(o.stride)) {
    const std::size_t j = i + static_cast<std::size_t>(o.gap);
    const FeatureFrame& fi = seq.frames[i];
    const FeatureFrame& fj = seq.frames[j];
    const auto T_W_Bi = groundtruth_at(seq.groundtruth, fi.t + offset);
    const auto T_W_Bj = groundtruth_at(seq.groundtruth, fj.t + offset);
    if (!T_W_Bi || !T_W_Bj) continue;
    const auto obs_i = normalized(fi);
    const auto obs_j = normalized(fj);
    PoseChangeWindow w;
    w.sequence = seq.name;
    w.frame_i = i;
    w.frame_j = j;
    w.t_i = fi.t;
    w.t_j = fj.t;
    w.focal_px = focal;
    double parallax = 0;
    for (const auto& x : fi.features) {  // track-id order: deterministic
      const auto a = obs_i.find(x.track_id);
      const auto b = obs_j.find(x.track_id);
      if (a == obs_i.end() || b == obs_j.end()) continue;
      w.correspondences.push_back({a->second.m, b->second.m, a->second.depth});
      parallax += (b->second.m - a->second.m).norm();
      if (a->second.depth) ++w.depth_available;
    }
    if (static_cast<int>(w.correspondences.size()) < o.min_correspondences) continue;
    w.parallax_px = focal * parallax / static_cast<double>(w.correspondences.size());
    if (w.parallax_px < o.min_parallax_px) continue;
    w.T_j_i_true = (*T_W_Bj * seq.camera.T_B_C).inverse() * (*T_W_Bi * seq.camera.T_B_C);
    if (w.T_j_i_true.t.norm() < o.min_baseline_m) continue;
    windows.push_back(std::move(w));
  }
  return windows;
}

std::vector<PoseChangeWindow> select_windows(std::vector<PoseChangeWindow> windows, int max_windows) {
  std::vector<PoseChangeWindow> out;
  const std::size_t n = windows.size();
  const std::size_t keep = max_windows <= 0 ? n : std::min(n, static_cast<std::size_t>(max_windows));
  out.reserve(keep);
  for (std::size_t k = 0; k < keep; ++k) out.push_back(std::move(windows[k * n / keep]));
  for (std::size_t k = 0; k < out.size(); ++k) out[k].index = static_cast<int>(k);
  return out;
}

std::vector<PoseChangeStudyRow> evaluate_pose_change_window(const PoseChangeWindow& w,
                                                            const PoseChangeStudyOptions& o) {
  PoseChangeOptions pco = o.pose_change;
  pco.focal_px = w.focal_px;
  pco.seed = o.seed;
  // One random order of the depth features per window; budget N keeps the first N (nested sets).
  std::vector<int> depth_idx;
  for (std::size_t k = 0; k < w.correspondences.size(); ++k)
    if (w.correspondences[k].depth_i) depth_idx.push_back(static_cast<int>(k));
  std::mt19937_64 rng(o.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(w.index));
  std::shuffle(depth_idx.begin(), depth_idx.end(), rng);

  const double baseline = w.T_j_i_true.t.norm();
  std::vector<PoseChangeStudyRow> rows;
  for (int budget : o.depth_budgets) {
    const int keep = budget == kAllDepths ? static_cast<int>(depth_idx.size())
                                          : std::min(budget, static_cast<int>(depth_idx.size()));
    std::vector<PoseChangeCorrespondence> c = w.correspondences;
    for (std::size_t r = static_cast<std::size_t>(keep); r < depth_idx.size(); ++r) c[depth_idx[r]].depth_i.reset();
    for (auto method : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
      PoseChangeStudyRow row;
      row.sequence = w.sequence;
      row.window = w.index;
      row.t_i = w.t_i;
      row.t_j = w.t_j;
      row.baseline_m = baseline;
      row.correspondences = static_cast<int>(c.size());
      row.budget = budget;
      row.depth_used = keep;
      row.method = method;
      row.rot_err_deg = row.trans_err_m = kNaN;
      const auto p = estimate_pose_change(c, method, pco, &row.reason);
      if (p) {
        row.returned = true;
        row.reason.clear();
        row.rot_err_deg = p->T_j_i.q.angularDistance(w.T_j_i_true.q) * kRadToDeg;
        row.trans_err_m = (p->T_j_i.t - w.T_j_i_true.t).norm();
        row.inliers = p->inliers;
        row.depth_inliers = p->depth_inliers;
        row.rotation_only = p->rotation_only;
        row.ok = row.rot_err_deg < o.success_rotation_deg &&
                 row.trans_err_m < o.success_translation_rel * baseline + o.success_translation_abs_m;
      }
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

std::pair<double, double> wilson_interval(int k, int n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double p = static_cast<double>(k) / n, z2n = z * z / n;
  const double centre = (p + z2n / 2.0) / (1.0 + z2n);
  const double half = z / (1.0 + z2n) * std::sqrt(p * (1.0 - p) / n + z2n / (4.0 * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::vector<PoseChangeStudySummary> summarize_pose_change_study(const std::vector<PoseChangeStudyRow>& rows,
                                                                const PoseChangeStudyOptions& o) {
  std::vector<PoseChangeStudySummary> out;
  for (int budget : o.depth_budgets) {
    for (auto method : {PoseChangeMethod::kHybrid, PoseChangeMethod::kPnp}) {
      PoseChangeStudySummary s;
      s.method = method;
      s.budget = budget;
      std::vector<double> rot, trans;
      double depth = 0;
      for (const auto& r : rows) {
        if (r.budget != budget || r.method != method) continue;
        ++s.windows;
        depth += r.depth_used;
        if (r.ok) ++s.successes;
        if (!r.returned) continue;
        ++s.returned;
        rot.push_back(r.rot_err_deg);
        trans.push_back(r.trans_err_m);
      }
      s.success_rate = s.windows ? static_cast<double>(s.successes) / s.windows : kNaN;
      std::tie(s.wilson_low, s.wilson_high) = wilson_interval(s.successes, s.windows);
      s.median_rot_err_deg = median(rot);
      s.median_trans_err_m = median(trans);
      s.mean_depth_used = s.windows ? depth / s.windows : kNaN;
      out.push_back(s);
    }
  }
  return out;
}

std::string budget_label(int budget) { return budget == kAllDepths ? "all" : std::to_string(budget); }

void write_pose_change_rows_csv(std::ostream& out, const std::vector<PoseChangeStudyRow>& rows) {
  out << "window,N,method,ok,rot_err_deg,trans_err_m,inliers,depth_inliers,sequence,t_i,t_j,baseline_m,"
         "correspondences,depth_used,returned,rotation_only,reason\n";
  for (const auto& r : rows) {
    out << r.window << ',' << budget_label(r.budget) << ',' << to_string(r.method) << ',' << (r.ok ? 1 : 0) << ','
        << num(r.rot_err_deg, 5) << ',' << num(r.trans_err_m, 5) << ',' << r.inliers << ',' << r.depth_inliers << ','
        << csv_field(r.sequence) << ',' << r.t_i << ',' << r.t_j << ',' << num(r.baseline_m, 5) << ','
        << r.correspondences << ',' << r.depth_used << ',' << (r.returned ? 1 : 0) << ','
        << (r.rotation_only ? 1 : 0) << ',' << csv_field(r.reason) << '\n';
  }
}

std::string pose_change_summary_markdown(const std::vector<PoseChangeStudySummary>& summary) {
  std::ostringstream s;
  s << "| N | method | windows | mean depth used | returned | success | rate [95 % Wilson] | median rot err [deg] | "
       "median trans err [m] |\n";
  s << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& x : summary) {
    auto or_dash = [](const std::string& v) { return v.empty() ? std::string("-") : v; };
    s << "| " << budget_label(x.budget) << " | " << to_string(x.method) << " | " << x.windows << " | "
      << num(x.mean_depth_used, 1) << " | " << x.returned << " | " << x.successes << " | "
      << or_dash(num(100.0 * x.success_rate, 1)) << " % [" << num(100.0 * x.wilson_low, 1) << ", "
      << num(100.0 * x.wilson_high, 1) << "] | " << or_dash(num(x.median_rot_err_deg, 3)) << " | "
      << or_dash(num(x.median_trans_err_m, 4)) << " |\n";
  }
  return s.str();
}

}  // namespace navaid::estimation
