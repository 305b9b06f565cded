#include "navaid/mapping/esdf_2d.hpp"

#include "navaid/mapping/config_schema.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <vector>

namespace navaid::mapping {

namespace {
const ConfigKey<std::string> kBackend{"mapping.esdf.backend",
                                      to_string(Esdf2dConfig{}.backend),
                                      {to_string(DistanceTransformBackend::kOpenCv),
                                       to_string(DistanceTransformBackend::kDynamicEdt)},
                                      "distance transform of the 2D ESDF (opencv is the faster, measured)"};
}  // namespace

ConfigSchema esdf_2d_config_schema() { return ConfigSchema().add(kBackend); }

Esdf2dConfig read_esdf_2d_config(const Config& config) {
  Esdf2dConfig e;
  e.backend = *distance_transform_backend_from_string(get(config, kBackend));  // get has checked the name
  return e;
}

Esdf2d::Esdf2d(const Esdf2dConfig& config) : config_(config) {}

const GridGeometry& Esdf2d::geometry() const {
  assert(field_);
  return field_->geometry();
}

const GridLayer<float>& Esdf2d::field() const {
  assert(field_);
  return *field_;
}

void Esdf2d::update(const CostMap& cost) {
  const GridGeometry& g = cost.geometry();
  if (!field_ || field_->geometry().width() != g.width() || field_->geometry().height() != g.height()) {
    obstacles_ = ImageU8(g.width(), g.height(), 1, 0);
    free_ = ImageU8(g.width(), g.height(), 1, 0);
  }
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      const bool obstacle = cost.is_obstacle(x, y);
      obstacles_.at(x, y) = obstacle ? 1 : 0;
      free_.at(x, y) = obstacle ? 0 : 1;
    }
  }
  distance_transform(obstacles_, config_.backend, to_obstacle_);
  distance_transform(free_, config_.backend, to_free_);
  if (!field_ || field_->geometry() != g) field_.emplace(g, 0.0F);
  const auto r = static_cast<float>(g.resolution());
  std::vector<float>& out = field_->cells().pixels;
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = obstacles_.pixels[i] != 0 ? -to_free_.pixels[i] * r : to_obstacle_.pixels[i] * r;
  }
}

std::optional<double> Esdf2d::distance(const Vec2& p_W) const {
  assert(field_);
  // The footstep search calls this a few times per primitive: no Cell2s, rows by pointer.
  const GridGeometry& g = field_->geometry();
  const double cx = p_W.x() / g.resolution() - g.origin_cell().x();  // continuous cell coordinate + 0.5
  const double cy = p_W.y() / g.resolution() - g.origin_cell().y();
  if (!(cx >= 0.0 && cy >= 0.0 && cx < g.width() && cy < g.height())) return std::nullopt;
  // Clamp into the square of cell centres: the border half-cell holds the border values.
  const double ux = std::min(std::max(cx - 0.5, 0.0), static_cast<double>(g.width() - 1));
  const double uy = std::min(std::max(cy - 0.5, 0.0), static_cast<double>(g.height() - 1));
  const int x0 = std::min(static_cast<int>(ux), std::max(g.width() - 2, 0));
  const int y0 = std::min(static_cast<int>(uy), std::max(g.height() - 2, 0));
  const int x1 = std::min(x0 + 1, g.width() - 1);
  const int y1 = std::min(y0 + 1, g.height() - 1);
  const double fx = ux - x0;
  const double fy = uy - y0;
  const float* row0 = field_->cells().data() + static_cast<std::size_t>(y0) * g.width();
  const float* row1 = field_->cells().data() + static_cast<std::size_t>(y1) * g.width();
  const double d00 = row0[x0];
  const double d10 = row0[x1];
  const double d01 = row1[x0];
  const double d11 = row1[x1];
  if (!std::isfinite(d00) || !std::isfinite(d10) || !std::isfinite(d01) || !std::isfinite(d11)) {
    return static_cast<double>(field_->at(static_cast<int>(cx), static_cast<int>(cy)));
  }
  return (1.0 - fy) * ((1.0 - fx) * d00 + fx * d10) + fy * ((1.0 - fx) * d01 + fx * d11);
}

std::optional<Vec2> Esdf2d::gradient(const Vec2& p_W) const {
  const std::optional<double> d = distance(p_W);
  if (!d) return std::nullopt;
  if (!std::isfinite(*d)) return Vec2::Zero();
  const double h = field_->geometry().resolution();
  Vec2 grad;
  for (int i = 0; i < 2; ++i) {
    const Vec2 step = Vec2::Unit(i) * h;
    const std::optional<double> plus = distance(p_W + step);
    const std::optional<double> minus = distance(p_W - step);
    if (plus && minus) {
      grad[i] = (*plus - *minus) / (2.0 * h);
    } else if (plus) {
      grad[i] = (*plus - *d) / h;
    } else if (minus) {
      grad[i] = (*d - *minus) / h;
    } else {
      grad[i] = 0.0;
    }
  }
  return grad;
}

}  // namespace navaid::mapping
