#include "navaid/planning/plan_png.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "navaid/core/errors.hpp"

namespace navaid::planning {

namespace {

const cv::Scalar kPalette[] = {{40, 40, 230}, {230, 120, 30}, {40, 170, 40}, {200, 60, 200}, {30, 200, 220}};

}  // namespace

void write_plan_png(const std::filesystem::path& path, const mapping::CostMap& cost, const PlanningProblem& problem,
                    const std::vector<LabelledPlan>& plans) {
  const mapping::GridGeometry& g = cost.geometry();
  // A few pixels per cell for small windows, one for big maps, at most ~1600 px a side.
  const int scale = std::clamp(1600 / std::max(g.width(), g.height()), 1, 8);
  const int w = g.width() * scale;
  const int h = g.height() * scale;
  const int line_height = 22;
  const int legend = line_height * (static_cast<int>(plans.size()) + 1) + 8;
  cv::Mat img(h + legend, std::max(w, 480), CV_8UC3, cv::Scalar(255, 255, 255));
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      const float c = cost.at(x, y);
      const int v = cost.is_obstacle(x, y) ? 0 : static_cast<int>(std::lround(255.0 - 200.0 * std::clamp(c, 0.0F, 1.0F)));
      cv::rectangle(img, cv::Rect(x * scale, (g.height() - 1 - y) * scale, scale, scale), cv::Scalar(v, v, v),
                    cv::FILLED);
    }
  }
  const auto pixel = [&](const Vec2& p) {
    const Vec2 u = (p - g.origin_W()) / g.resolution() * scale;
    return cv::Point(static_cast<int>(std::lround(u.x())), static_cast<int>(std::lround(h - u.y())));
  };
  const int thickness = std::max(1, scale / 2 + 1);
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const Plan& p = *plans[i].plan;
    const cv::Scalar colour = kPalette[i % std::size(kPalette)];
    for (std::size_t k = 1; k < p.path_W.size(); ++k) {
      cv::line(img, pixel(p.path_W[k - 1]), pixel(p.path_W[k]), colour, thickness, cv::LINE_AA);
    }
    const std::string text =
        p.found() ? fmt::format("{}: {:.2f} m, {} nodes, {:.1f} ms", plans[i].label, p.length_m, p.expanded,
                                1e3 * p.time_s)
                  : fmt::format("{}: {} ({})", plans[i].label, to_string(p.reason), p.detail);
    const int baseline = h + line_height * static_cast<int>(i + 1);
    cv::line(img, cv::Point(8, baseline - 6), cv::Point(36, baseline - 6), colour, 3);
    cv::putText(img, text.substr(0, 110), cv::Point(44, baseline), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  const int radius = std::max(4, 2 * scale);
  const cv::Point start = pixel(problem.start.position);
  cv::circle(img, start, radius, cv::Scalar(40, 160, 40), cv::FILLED, cv::LINE_AA);
  const double tick = 6.0 * radius;
  cv::line(img, start,
           start + cv::Point(static_cast<int>(tick * std::cos(problem.start.yaw_rad)),
                             static_cast<int>(-tick * std::sin(problem.start.yaw_rad))),
           cv::Scalar(40, 160, 40), 2, cv::LINE_AA);
  if (problem.goal_W) {
    cv::circle(img, pixel(*problem.goal_W), radius, cv::Scalar(30, 30, 220), cv::FILLED, cv::LINE_AA);
  } else if (problem.goal_direction_rad) {
    const double a = *problem.goal_direction_rad;
    const double length = 12.0 * radius;
    cv::arrowedLine(img, start,
                    start + cv::Point(static_cast<int>(length * std::cos(a)), static_cast<int>(-length * std::sin(a))),
                    cv::Scalar(30, 30, 220), 2, cv::LINE_AA, 0, 0.2);
  }
  cv::putText(img,
              fmt::format("{} x {} cells of {:.2f} m; start green, goal red; obstacles black, unknown grey", g.width(),
                          g.height(), g.resolution()),
              cv::Point(8, h + legend - 8), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(80, 80, 80), 1, cv::LINE_AA);
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), img);
  } catch (const cv::Exception& e) {
    throw IoError(path.string(), e.what());
  }
  if (!ok) throw IoError(path.string(), "cannot write PNG");
}

}  // namespace navaid::planning
