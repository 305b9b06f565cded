#include "navaid/mapping/map_top_view.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "navaid/core/errors.hpp"

namespace navaid::mapping {

namespace {
cv::Scalar bgr(SemanticClass c) {
  const auto& rgb = semantic_class_info(c).rgb;
  return {static_cast<double>(rgb[2]), static_cast<double>(rgb[1]), static_cast<double>(rgb[0])};
}
}  // namespace

MapTopView::MapTopView(double cell_m) : cell_m_(cell_m) {
  if (!(cell_m > 0.0)) throw Error("MapTopView: cell size must be positive");
}

void MapTopView::add_voxels(const MapVoxels& voxels, double max_z_W) {
  // Highest voxel per cell of this snapshot replaces what the cell showed.
  std::map<std::pair<long, long>, std::pair<float, SemanticClass>> top;
  for (const auto& v : voxels) {
    if (v.center_W.z() > max_z_W) continue;
    const std::pair<long, long> key{static_cast<long>(std::floor(v.center_W.x() / cell_m_)),
                                    static_cast<long>(std::floor(v.center_W.y() / cell_m_))};
    const float z = static_cast<float>(v.center_W.z());
    auto it = top.find(key);
    if (it == top.end() || z > it->second.first) top[key] = {z, v.semantic};
  }
  for (const auto& [key, value] : top) cells_[key] = value.second;
}

void MapTopView::add_path_point(const Vec3& p_W) { path_.push_back(p_W); }

std::size_t MapTopView::painted_cells() const { return cells_.size(); }

void MapTopView::write_png(const std::filesystem::path& file, int max_side_px) const {
  if (cells_.empty() && path_.empty()) throw IoError(file.string(), "nothing to draw: no voxels and no path");
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& [key, semantic] : cells_) {
    x0 = std::min(x0, key.first * cell_m_), x1 = std::max(x1, (key.first + 1) * cell_m_);
    y0 = std::min(y0, key.second * cell_m_), y1 = std::max(y1, (key.second + 1) * cell_m_);
  }
  for (const auto& p : path_) x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  x0 -= 1.0, y0 -= 1.0, x1 += 1.0, y1 += 1.0;
  // At most 40 px per metre (a short walk stays readable), at most max_side_px in all.
  const double px_per_m = std::min(40.0, max_side_px / std::max(x1 - x0, y1 - y0));
  const int w = static_cast<int>(std::ceil((x1 - x0) * px_per_m)), h = static_cast<int>(std::ceil((y1 - y0) * px_per_m));
  const int legend_h = 22;
  std::set<SemanticClass> seen;
  for (const auto& [key, semantic] : cells_) seen.insert(semantic);
  const int legend_rows = static_cast<int>((seen.size() + 3) / 4) + 1;
  cv::Mat img(h + legend_rows * legend_h, std::max(w, 640), CV_8UC3, cv::Scalar(255, 255, 255));
  auto to_px = [&](double x, double y) {
    return cv::Point(static_cast<int>((x - x0) * px_per_m), static_cast<int>((y1 - y) * px_per_m));
  };
  const int cell_px = std::max(1, static_cast<int>(std::ceil(cell_m_ * px_per_m)));
  for (const auto& [key, semantic] : cells_) {
    const cv::Point p = to_px(key.first * cell_m_, (key.second + 1) * cell_m_);
    cv::rectangle(img, cv::Rect(p.x, p.y, cell_px, cell_px), bgr(semantic), cv::FILLED);
  }
  for (std::size_t i = 1; i < path_.size(); ++i)
    cv::line(img, to_px(path_[i - 1].x(), path_[i - 1].y()), to_px(path_[i].x(), path_[i].y()), cv::Scalar(0, 0, 0), 2,
             cv::LINE_AA);
  // 1 m scale bar, bottom left of the map area.
  const cv::Point bar0(10, h - 10), bar1(10 + static_cast<int>(px_per_m), h - 10);
  cv::line(img, bar0, bar1, cv::Scalar(0, 0, 0), 3);
  cv::putText(img, "1 m", cv::Point(bar1.x + 6, h - 5), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  int k = 0;
  for (const auto c : seen) {
    const int row = k / 4, col = k % 4;
    const cv::Point at(10 + col * 160, h + row * legend_h + 6);
    cv::rectangle(img, cv::Rect(at.x, at.y, 14, 14), bgr(c), cv::FILLED);
    cv::rectangle(img, cv::Rect(at.x, at.y, 14, 14), cv::Scalar(0, 0, 0), 1);
    cv::putText(img, std::string(semantic_class_name(c)), cv::Point(at.x + 20, at.y + 12), cv::FONT_HERSHEY_SIMPLEX,
                0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    ++k;
  }
  cv::putText(img, "walked path (black), highest occupied voxel per cell in its class colour",
              cv::Point(10, h + (legend_rows - 1) * legend_h + 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0),
              1, cv::LINE_AA);
  if (!cv::imwrite(file.string(), img)) throw IoError(file.string(), "cannot write the PNG");
}

}  // namespace navaid::mapping
