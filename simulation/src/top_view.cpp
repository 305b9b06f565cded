#include "navaid/simulation/top_view.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/scenario.hpp"

namespace navaid::simulation {

Eigen::Vector2i TopView::pixel(const Vec2& p) const {
  return Eigen::Vector2i(static_cast<int>(std::floor((p.x() - top_left.x()) / metres_per_pixel)),
                         static_cast<int>(std::floor((top_left.y() - p.y()) / metres_per_pixel)));
}

namespace {

cv::Point to_cv(const TopView& v, const Vec2& p) {
  // Sub-pixel precision (shift 4) for smooth anti-aliased overlays.
  const double col = (p.x() - v.top_left.x()) / v.metres_per_pixel, row = (v.top_left.y() - p.y()) / v.metres_per_pixel;
  return cv::Point(static_cast<int>(std::lround(col * 16.0)), static_cast<int>(std::lround(row * 16.0)));
}

void draw_dashed(cv::Mat& img, const TopView& v, const std::vector<Vec2>& path, const cv::Scalar& colour) {
  const double dash = 5.0 * v.metres_per_pixel;  // 5 px on, 5 px off
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Vec2 a = path[i], b = path[i + 1];
    const double len = (b - a).norm();
    for (double s = 0.0; s < len; s += 2.0 * dash) {
      const Vec2 p = a + (b - a) * (s / len), q = a + (b - a) * (std::min(s + dash, len) / len);
      cv::line(img, to_cv(v, p), to_cv(v, q), colour, 1, cv::LINE_AA, 4);
    }
  }
}

void draw_scale_bar(cv::Mat& img, double mpp) {
  const double target = 0.2 * img.cols * mpp;
  double length = 1.0;
  for (double c : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0})
    if (c <= target) length = c;
  const int px = static_cast<int>(std::lround(length / mpp));
  const std::string label = std::to_string(static_cast<int>(length)) + " m";
  int base = 0;
  const cv::Size ts = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &base);
  // Bottom-right, right-aligned: paths of the scenarios start near the bottom-left corner.
  const int right = img.cols - 10, y0 = img.rows - 12;
  cv::rectangle(img, cv::Point(right - std::max(px, ts.width) - 4, y0 - ts.height - 10), cv::Point(right + 4, y0 + 6),
                cv::Scalar(255, 255, 255), cv::FILLED);
  cv::rectangle(img, cv::Point(right - px, y0), cv::Point(right, y0 + 3), cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(img, label, cv::Point(right - ts.width, y0 - 5), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
}

}  // namespace

TopView render_top_view(const RayCaster& caster, const TopViewOptions& o) {
  if (!(o.metres_per_pixel > 0.0) || !std::isfinite(o.metres_per_pixel)) throw Error("top view: metres_per_pixel must be > 0");
  const AxisAlignedBox wb = caster.world().bounds();
  Vec2 lo, hi;
  if (o.region) {
    lo = o.region->first;
    hi = o.region->second;
  } else {
    if (wb.empty) throw Error("top view: empty world and no region");
    lo = wb.min.head<2>() - Vec2::Constant(o.margin_m);
    hi = wb.max.head<2>() + Vec2::Constant(o.margin_m);
  }
  if (!(hi.array() > lo.array()).all()) throw Error("top view: empty region");
  const double w = std::ceil((hi.x() - lo.x()) / o.metres_per_pixel), h = std::ceil((hi.y() - lo.y()) / o.metres_per_pixel);
  if (w > 8192 || h > 8192) throw Error("top view: image larger than 8192 pixels; use more metres per pixel");

  TopView v;
  v.metres_per_pixel = o.metres_per_pixel;
  v.top_left = Vec2(lo.x(), hi.y());
  v.image = ImageU8(static_cast<int>(w), static_cast<int>(h), 3);
  const double z_top = (wb.empty ? 0.0 : wb.max.z()) + 1.0;
  const Vec3 down(0.0, 0.0, -1.0);

  // First visible (non-hidden) surface per pixel.
  std::vector<double> z(static_cast<std::size_t>(w * h), std::numeric_limits<double>::quiet_NaN());
  std::vector<std::uint8_t> cls(z.size(), 0);
  double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
  for (int r = 0; r < v.image.height; ++r)
    for (int c = 0; c < v.image.width; ++c) {
      const Vec3 origin(lo.x() + (c + 0.5) * o.metres_per_pixel, hi.y() - (r + 0.5) * o.metres_per_pixel, z_top);
      double t_min = 0.0;
      for (int k = 0; k < 16; ++k) {
        const auto hit = caster.cast(origin, down, std::numeric_limits<double>::infinity(), t_min);
        if (!hit) break;
        if (std::find(o.hidden_classes.begin(), o.hidden_classes.end(), hit->semantic) != o.hidden_classes.end()) {
          t_min = hit->distance + 1e-4;
          continue;
        }
        const std::size_t i = static_cast<std::size_t>(r) * v.image.width + c;
        z[i] = hit->point.z();
        cls[i] = static_cast<std::uint8_t>(hit->semantic);
        z_lo = std::min(z_lo, z[i]);
        z_hi = std::max(z_hi, z[i]);
        break;
      }
    }
  // Shade: colour x (0.6 + 0.4 (z - z_lo) / (z_hi - z_lo)); the highest surfaces (all, when flat)
  // keep their colour.
  const double span = z_hi - z_lo;
  for (int r = 0; r < v.image.height; ++r)
    for (int c = 0; c < v.image.width; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * v.image.width + c;
      for (int ch = 0; ch < 3; ++ch) {
        if (std::isnan(z[i])) {
          v.image.at(c, r, ch) = o.background[static_cast<std::size_t>(ch)];
        } else {
          const double shade = span > 0.0 ? 0.6 + 0.4 * (z[i] - z_lo) / span : 1.0;
          const double value = shade * semantic_classes()[cls[i]].rgb[static_cast<std::size_t>(ch)];
          v.image.at(c, r, ch) = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
        }
      }
    }

  cv::Mat img(v.image.height, v.image.width, CV_8UC3, v.image.data());  // RGB order, wraps without copy
  for (const auto& p : o.other_paths) draw_dashed(img, v, p, cv::Scalar(200, 0, 200));
  if (o.path.size() >= 2) {
    std::vector<cv::Point> pts;
    for (const Vec2& p : o.path) pts.push_back(to_cv(v, p));
    cv::polylines(img, pts, false, cv::Scalar(20, 80, 255), 2, cv::LINE_AA, 4);
  }
  if (o.markers && !o.path.empty()) {
    // Goal first, then a smaller start disc on top, so that both show on closed loops.
    cv::circle(img, to_cv(v, o.path.back()), 6 * 16, cv::Scalar(220, 0, 0), cv::FILLED, cv::LINE_AA, 4);
    cv::circle(img, to_cv(v, o.path.front()), 4 * 16, cv::Scalar(0, 170, 0), cv::FILLED, cv::LINE_AA, 4);
  }
  if (o.scale_bar && img.cols >= 80 && img.rows >= 40) draw_scale_bar(img, o.metres_per_pixel);
  return v;
}

TopViewOptions scenario_map_options(const Scenario& scenario, double width_px, const std::vector<Vec2>* walked) {
  TopViewOptions o;
  const Vec2 lo = scenario.extent.min.head<2>(), hi = scenario.extent.max.head<2>();
  o.margin_m = 0.03 * (hi - lo).maxCoeff();
  o.region = std::make_pair(lo - Vec2::Constant(o.margin_m), hi + Vec2::Constant(o.margin_m));
  o.metres_per_pixel = (hi.x() - lo.x() + 2.0 * o.margin_m) / width_px;
  o.path = walked ? *walked : scenario.path;
  for (const MovingObject& m : scenario.moving)
    if (m.path.size() >= 2) {
      o.other_paths.push_back(m.path);
      if (m.loop) o.other_paths.back().push_back(m.path.front());
    }
  return o;
}

}  // namespace navaid::simulation
