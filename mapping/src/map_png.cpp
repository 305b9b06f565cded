#include "navaid/mapping/map_png.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"

namespace navaid::mapping {

namespace {

const cv::Vec3b kUnknown(128, 128, 128);
const cv::Scalar kText(20, 20, 20);
constexpr int kLegendHeight = 56;
constexpr double kFontScale = 0.4;

// 256 BGR colours of an OpenCV colour map.
std::vector<cv::Vec3b> colormap_lut(int colormap) {
  cv::Mat ramp(256, 1, CV_8UC1);
  for (int i = 0; i < 256; ++i) ramp.at<std::uint8_t>(i) = static_cast<std::uint8_t>(i);
  cv::Mat colours;
  cv::applyColorMap(ramp, colours, colormap);
  std::vector<cv::Vec3b> lut(256);
  for (int i = 0; i < 256; ++i) lut[static_cast<std::size_t>(i)] = colours.at<cv::Vec3b>(i);
  return lut;
}

// Red (negative) - white (0) - blue (positive), for signed fields.
std::vector<cv::Vec3b> diverging_lut() {
  std::vector<cv::Vec3b> lut(256);
  const cv::Vec3d red(40, 40, 190), white(250, 250, 250), blue(180, 90, 30);
  for (int i = 0; i < 256; ++i) {
    const double t = i / 255.0;
    const cv::Vec3d c = t < 0.5 ? red + (white - red) * (t / 0.5) : white + (blue - white) * ((t - 0.5) / 0.5);
    lut[static_cast<std::size_t>(i)] = cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                                                 cv::saturate_cast<uchar>(c[2]));
  }
  return lut;
}

struct ColourScale {
  std::vector<cv::Vec3b> lut;
  double lo;
  double hi;
  cv::Vec3b operator()(double v) const {
    if (!std::isfinite(v)) return kUnknown;
    const double t = hi > lo ? (v - lo) / (hi - lo) : 0.5;
    return lut[static_cast<std::size_t>(std::lround(std::clamp(t, 0.0, 1.0) * 255.0))];
  }
};

int pixels_per_cell(const GridGeometry& g) { return std::max(1, 400 / std::max(g.width(), g.height())); }

// The map, north up: grid row y = 0 (south) is the image's bottom row.
cv::Mat render(const GridGeometry& g, const std::function<cv::Vec3b(int, int)>& colour) {
  const int s = pixels_per_cell(g);
  cv::Mat img(g.height() * s, g.width() * s, CV_8UC3);
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      img(cv::Rect(x * s, (g.height() - 1 - y) * s, s, s)).setTo(colour(x, y));
    }
  }
  return img;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, int x, int y) {
  cv::putText(img, s, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, kFontScale, kText, 1, cv::LINE_AA);
}

// Colour bar from lo to hi with three labelled ticks, a title, and an optional marked value.
cv::Mat colourbar_legend(int width, const ColourScale& scale, const std::string& title, bool show_unknown,
                         const std::vector<std::pair<double, std::string>>& marks = {}) {
  cv::Mat strip(kLegendHeight, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int x0 = 8;
  const int x1 = width - (show_unknown ? 90 : 8);
  for (int x = x0; x < x1; ++x) {
    const double t = static_cast<double>(x - x0) / std::max(1, x1 - x0 - 1);
    strip(cv::Rect(x, 16, 1, 14)).setTo(scale(scale.lo + t * (scale.hi - scale.lo)));
  }
  text(strip, title, x0, 11);
  for (int k = 0; k <= 2; ++k) {
    const int x = x0 + k * (x1 - x0 - 1) / 2;
    cv::line(strip, cv::Point(x, 30), cv::Point(x, 34), kText);
    text(strip, number(scale.lo + k * (scale.hi - scale.lo) / 2.0), std::clamp(x - 12, 0, width - 40), 47);
  }
  for (const auto& [value, label] : marks) {
    if (!(scale.hi > scale.lo)) continue;
    const int x = x0 + static_cast<int>(std::lround((value - scale.lo) / (scale.hi - scale.lo) * (x1 - x0 - 1)));
    cv::line(strip, cv::Point(x, 13), cv::Point(x, 33), cv::Scalar(0, 0, 0), 2);
    text(strip, label, std::clamp(x + 4, 0, width - 70), 11);
  }
  if (show_unknown) {
    strip(cv::Rect(width - 80, 16, 14, 14)).setTo(kUnknown);
    text(strip, "unknown", width - 62, 28);
  }
  return strip;
}

// One swatch per class.
cv::Mat swatch_legend(int width, const std::string& title, const std::vector<std::pair<std::string, cv::Vec3b>>& items) {
  cv::Mat strip(kLegendHeight, width, CV_8UC3, cv::Scalar(255, 255, 255));
  text(strip, title, 8, 11);
  int x = 8;
  for (const auto& [label, colour] : items) {
    strip(cv::Rect(x, 20, 14, 14)).setTo(colour);
    text(strip, label, x + 18, 32);
    x += 18 + 8 * static_cast<int>(label.size()) + 12;
  }
  return strip;
}

void write(const std::filesystem::path& path, const cv::Mat& map, const cv::Mat& legend) {
  cv::Mat out;
  cv::vconcat(map, legend, out);
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), out);
  } catch (const cv::Exception& e) {
    throw IoError(path.string(), std::string("cannot write the PNG: ") + e.what());
  }
  if (!ok) throw IoError(path.string(), "cannot write the PNG");
}

// Range of the finite values of a layer (lo == hi when all are equal; 0..1 when none is finite).
std::pair<double, double> finite_range(const std::vector<float>& values) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const float v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, static_cast<double>(v));
    hi = std::max(hi, static_cast<double>(v));
  }
  return lo <= hi ? std::make_pair(lo, hi) : std::make_pair(0.0, 1.0);
}

}  // namespace

void write_height_map_png(const std::filesystem::path& path, const HeightMap& map) {
  const auto [lo, hi] = finite_range(map.cells().pixels);
  const ColourScale scale{colormap_lut(cv::COLORMAP_VIRIDIS), lo, hi};
  const cv::Mat img = render(map.geometry(), [&](int x, int y) { return scale(map.at(x, y)); });
  write(path, img, colourbar_legend(img.cols, scale, "height of the highest occupied voxel [m, W z]", true));
}

void write_undulation_map_png(const std::filesystem::path& path, const UndulationMap& map) {
  const cv::Vec3b flat(235, 235, 235), step(0, 120, 255);
  const cv::Mat img = render(map.geometry(), [&](int x, int y) { return map.at(x, y) != 0 ? step : flat; });
  write(path, img, swatch_legend(img.cols, "undulation (Sobel on height)", {{"0 flat/unknown", flat}, {"1 step", step}}));
}

void write_collision_map_png(const std::filesystem::path& path, const CollisionMap& map) {
  const ColourScale scale{colormap_lut(cv::COLORMAP_INFERNO), 0.0, 1.0};
  const cv::Mat img = render(map.geometry(), [&](int x, int y) { return scale(map.at(x, y)); });
  write(path, img, colourbar_legend(img.cols, scale, "collision probability p(g), eq. 9", true));
}

void write_cost_map_png(const std::filesystem::path& path, const CostMap& map) {
  const ColourScale scale{colormap_lut(cv::COLORMAP_TURBO), 0.0, 1.0};
  const cv::Mat img = render(map.geometry(), [&](int x, int y) { return scale(map.at(x, y)); });
  const std::string title = "cost, eq. 8 (inflation r = " + number(map.inflation_radius_m()) + " m)";
  write(path, img,
        colourbar_legend(img.cols, scale, title, false, {{map.obstacle_threshold(), "obstacle >"}}));
}

void write_esdf_png(const std::filesystem::path& path, const Esdf2d& esdf) {
  const auto& field = esdf.field();
  const auto [lo, hi] = finite_range(field.cells().pixels);
  const double extent = std::max({std::abs(lo), std::abs(hi), field.geometry().resolution()});
  const ColourScale scale{diverging_lut(), -extent, extent};
  const cv::Mat img = render(field.geometry(), [&](int x, int y) {
    const float d = field.at(x, y);
    return std::isinf(d) ? scale(d > 0 ? extent : -extent) : scale(d);
  });
  write(path, img, colourbar_legend(img.cols, scale, "signed distance to obstacles [m] (<0 inside)", false));
}

}  // namespace navaid::mapping
