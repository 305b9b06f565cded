#include "navaid/planning/route_png.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "navaid/core/errors.hpp"
#include "navaid/planning/route_subgoals.hpp"

namespace navaid::planning {

void write_route_png(const std::filesystem::path& path, const FootGraph& graph, const Route& route,
                     const GeoPoint& from, const GeoPoint& to, const std::string& legend) {
  const LocalEnu enu(GeodeticOrigin{from.lat_deg, from.lon_deg, 0.0});
  // The view: the route (or the two points) with a 30 m margin.
  Vec2 lo = enu.to_enu(from).cwiseMin(enu.to_enu(to));
  Vec2 hi = enu.to_enu(from).cwiseMax(enu.to_enu(to));
  for (const GeoPoint& p : route.points) {
    lo = lo.cwiseMin(enu.to_enu(p));
    hi = hi.cwiseMax(enu.to_enu(p));
  }
  lo -= Vec2(30, 30);
  hi += Vec2(30, 30);
  const double span = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const Vec2 centre = 0.5 * (lo + hi);  // a square view centred on the route
  lo = centre - Vec2(span / 2, span / 2);
  hi = centre + Vec2(span / 2, span / 2);
  const int size = 1000;
  const double scale = size / span;
  const int legend_h = 30;
  cv::Mat img(size + legend_h, size, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto pixel = [&](const GeoPoint& g) {
    const Vec2 u = (enu.to_enu(g) - lo) * scale;
    return cv::Point(static_cast<int>(std::lround(u.x())), static_cast<int>(std::lround(size - u.y())));
  };
  const auto inside = [&](const Vec2& p) { return p.x() >= lo.x() && p.y() >= lo.y() && p.x() <= hi.x() && p.y() <= hi.y(); };
  for (const FootEdge& e : graph.edges) {
    const GeoPoint a{graph.nodes[e.a].lat_deg, graph.nodes[e.a].lon_deg};
    const GeoPoint b{graph.nodes[e.b].lat_deg, graph.nodes[e.b].lon_deg};
    if (!inside(enu.to_enu(a)) && !inside(enu.to_enu(b))) continue;
    const FootWay& w = graph.ways[e.way];
    cv::Scalar colour(150, 150, 150);
    if (w.kind == FootWayKind::kSidewalk || w.kind == FootWayKind::kFootway) colour = cv::Scalar(230, 180, 120);
    if (w.kind == FootWayKind::kCrossing) colour = cv::Scalar(60, 160, 60);
    if (w.kind == FootWayKind::kSteps) colour = cv::Scalar(0, 140, 255);
    if (w.is_road()) colour = cv::Scalar(90, 90, 90);
    cv::line(img, pixel(a), pixel(b), colour, w.is_road() ? 3 : 2, cv::LINE_AA);
  }
  for (const Landmark& l : graph.landmarks) {
    const cv::Point p = pixel(GeoPoint{l.lat_deg, l.lon_deg});
    if (p.x >= 0 && p.y >= 0 && p.x < size && p.y < size) cv::rectangle(img, p - cv::Point(3, 3), p + cv::Point(3, 3), cv::Scalar(0, 0, 0), cv::FILLED);
  }
  for (std::size_t i = 0; i + 1 < route.points.size(); ++i) {
    cv::line(img, pixel(route.points[i]), pixel(route.points[i + 1]), cv::Scalar(30, 30, 220), 4, cv::LINE_AA);
  }
  for (const RouteCrossing& c : route.crossings) {
    cv::Scalar colour(200, 60, 200);
    if (c.info.control == CrossingControl::kTrafficSignals) colour = cv::Scalar(40, 170, 40);
    if (c.info.control == CrossingControl::kMarked) colour = cv::Scalar(0, 210, 230);
    cv::circle(img, pixel(route.points[std::min(c.point, route.points.size() - 1)]), 7, colour, cv::FILLED, cv::LINE_AA);
  }
  cv::circle(img, pixel(from), 8, cv::Scalar(40, 170, 40), cv::FILLED, cv::LINE_AA);
  cv::circle(img, pixel(to), 8, cv::Scalar(30, 30, 220), cv::FILLED, cv::LINE_AA);
  const double bar = std::pow(10.0, std::floor(std::log10(span / 4)));
  cv::line(img, cv::Point(10, size - 10), cv::Point(10 + static_cast<int>(bar * scale), size - 10), cv::Scalar(0, 0, 0), 2);
  cv::putText(img, cv::format("%.0f m", bar), cv::Point(12, size - 16), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1);
  cv::putText(img, legend, cv::Point(8, size + 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  try {
    if (!cv::imwrite(path.string(), img)) throw IoError(path.string(), "cannot write the PNG");
  } catch (const cv::Exception& e) {
    throw IoError(path.string(), std::string("cannot write the PNG: ") + e.what());
  }
}

}  // namespace navaid::planning
