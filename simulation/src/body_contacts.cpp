#include "navaid/simulation/body_contacts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {

void require_body_key(bool ok, const std::string& key, const char* range) {
  if (!ok) throw ConfigError("", key, std::string("must be ") + range);
}

/// The horizontal gap between p and a box, for the quick rejection of far primitives.
double box_gap(const AxisAlignedBox& b, const Vec2& p) {
  const double dx = std::max({b.min.x() - p.x(), 0.0, p.x() - b.max.x()});
  const double dy = std::max({b.min.y() - p.y(), 0.0, p.y() - b.max.y()});
  return std::hypot(dx, dy);
}

}  // namespace

std::string_view to_string(BodyPart part) {
  switch (part) {
    case BodyPart::kLegs: return "legs";
    case BodyPart::kTorso: return "torso";
    case BodyPart::kHead: return "head";
    case BodyPart::kCane: return "cane";
  }
  return "?";
}

void validate(const BodyModel& b) {
  require_body_key(b.radius_m > 0.05 && b.radius_m < 0.6, "user.body.radius_m", "in (0.05, 0.6) m");
  require_body_key(b.height_m > 1.0 && b.height_m < 2.3, "user.body.height_m", "in (1, 2.3) m");
  require_body_key(b.step_over_m >= 0 && b.step_over_m < b.legs_top_m, "user.body.step_over_m", "in [0, legs_top_m) m");
  require_body_key(b.legs_top_m < b.head_bottom_m, "user.body.legs_top_m", "below head_bottom_m");
  require_body_key(b.head_bottom_m < b.height_m, "user.body.head_bottom_m", "below height_m");
}

void validate(const CaneModel& c) {
  require_body_key(c.length_m > 0.3 && c.length_m < 2.0, "user.cane.length_m", "in (0.3, 2) m");
  require_body_key(c.sweep_half_angle_rad >= 0 && c.sweep_half_angle_rad < 1.4, "user.cane.sweep_half_angle_deg",
          "in [0, 80) deg");
  require_body_key(c.detect_height_m > 0.02 && c.detect_height_m < 1.5, "user.cane.detect_height_m", "in (0.02, 1.5) m");
  require_body_key(c.tip_radius_m > 0 && c.tip_radius_m < 0.2, "user.cane.tip_radius_m", "in (0, 0.2) m");
}

ContactMonitor::ContactMonitor(const World& statics, double ground_z_m, const BodyModel& body, const CaneModel& cane)
    : statics_(&statics), ground_z_(ground_z_m), body_(body), cane_(cane) {
  validate(body_);
  if (cane_.enabled) validate(cane_);
  static_bounds_.reserve(statics.size());
  for (const auto& p : statics.primitives()) static_bounds_.push_back(bounds_of(p.shape));
}

void ContactMonitor::check_world(const World& world, bool moving, const Vec2& position, double heading_rad,
                                 std::vector<Hit>& hits) {
  const double g = ground_z_;
  // A hit that touches several parts at once is named by the part it covers most (a wall or a
  // cabinet meets the legs first, a board hung at 1.3-1.9 m the head).
  const std::array<std::pair<BodyPart, std::pair<double, double>>, 3> parts = {{
      {BodyPart::kLegs, {body_.step_over_m, body_.legs_top_m}},
      {BodyPart::kTorso, {body_.legs_top_m, body_.head_bottom_m}},
      {BodyPart::kHead, {body_.head_bottom_m, body_.height_m}},
  }};
  const double reach = std::max(body_.radius_m, cane_.enabled ? cane_.length_m + cane_.tip_radius_m : 0.0);
  for (std::uint32_t i = 0; i < world.size(); ++i) {
    const Shape& shape = world.primitive(i).shape;
    const AxisAlignedBox bounds = moving ? bounds_of(shape) : static_bounds_[i];
    if (box_gap(bounds, position) > reach) continue;
    std::optional<BodyPart> named;
    double most = 0;
    for (const auto& [part, band] : parts) {
      if (horizontal_distance(shape, position, g + band.first, g + band.second) >= body_.radius_m) continue;
      const double overlap = std::min(band.second, bounds.max.z() - g) - std::max(band.first, bounds.min.z() - g);
      if (!named || overlap > most) named = part, most = overlap;
    }
    if (named) hits.push_back({*named, moving, i});
    if (!cane_.enabled) continue;
    // The swept sector: the tip's arc and two inner arcs the shaft passes over near the ground.
    constexpr int kAngles = 9;
    for (double fraction : {1.0, 0.8, 0.6}) {
      bool found = false;
      for (int k = 0; k < kAngles && !found; ++k) {
        const double bearing = cane_.sweep_half_angle_rad * (2.0 * k / (kAngles - 1) - 1.0);
        const double a = heading_rad + bearing, d = fraction * cane_.length_m;
        const Vec2 q = position + d * Vec2(std::cos(a), std::sin(a));
        if (horizontal_distance(shape, q, g + 0.02, g + cane_.detect_height_m) < cane_.tip_radius_m) {
          hits.push_back({BodyPart::kCane, moving, i});
          if (!cane_touch_ || d < cane_touch_->distance_m) cane_touch_ = CaneTouch{bearing, d, moving, i};
          found = true;
        }
      }
      if (found) break;
    }
  }
}

bool ContactMonitor::body_touches(std::uint32_t i, const Vec2& p) const {
  if (box_gap(static_bounds_[i], p) > body_.radius_m) return false;
  return horizontal_distance(statics_->primitive(i).shape, p, ground_z_ + body_.step_over_m, ground_z_ + body_.height_m) <
         body_.radius_m;
}

std::optional<std::uint32_t> ContactMonitor::blocked_along(const Vec2& position, double heading_rad,
                                                           double distance_m) const {
  const Vec2 dir(std::cos(heading_rad), std::sin(heading_rad));
  const int steps = std::max(1, static_cast<int>(std::ceil(distance_m / 0.05)));
  for (std::uint32_t i = 0; i < statics_->size(); ++i) {
    if (box_gap(static_bounds_[i], position) > distance_m + body_.radius_m) continue;
    if (body_touches(i, position)) continue;  // touching it already: not where the guidance leads
    for (int k = 1; k <= steps; ++k)
      if (body_touches(i, position + dir * (distance_m * k / steps))) return i;
  }
  return std::nullopt;
}

std::optional<CaneTouch> ContactMonitor::bump(const Vec2& from, const Vec2& to, double heading_rad) const {
  const double z_lo = ground_z_ + body_.step_over_m, z_hi = ground_z_ + body_.height_m;
  std::optional<CaneTouch> hit;
  for (std::uint32_t i = 0; i < statics_->size(); ++i) {
    if (box_gap(static_bounds_[i], to) > body_.radius_m) continue;
    const Shape& shape = statics_->primitive(i).shape;
    const double d_to = horizontal_distance(shape, to, z_lo, z_hi);
    // A touch gives 3 cm (clothes, an arm held out) before it stops the body, so the contact
    // monitor, sampling slower than the steps, sees every bump.
    constexpr double kGive = 0.03;
    if (d_to >= body_.radius_m - kGive || d_to >= horizontal_distance(shape, from, z_lo, z_hi)) continue;
    if (hit && d_to >= hit->distance_m) continue;
    // Where it is: down the distance's gradient (central differences over 1 cm).
    constexpr double e = 0.01;
    const Vec2 g(horizontal_distance(shape, to + Vec2(e, 0), z_lo, z_hi) - horizontal_distance(shape, to - Vec2(e, 0), z_lo, z_hi),
                 horizontal_distance(shape, to + Vec2(0, e), z_lo, z_hi) - horizontal_distance(shape, to - Vec2(0, e), z_lo, z_hi));
    const double toward = g.norm() > 0 ? std::atan2(-g.y(), -g.x()) : heading_rad;
    hit = CaneTouch{std::remainder(toward - heading_rad, 2 * M_PI), d_to, false, i};
  }
  return hit;
}

std::vector<Contact> ContactMonitor::update(double t_s, const Vec2& position, double heading_rad, const World& moving) {
  cane_touch_.reset();
  std::vector<Hit> hits;
  check_world(*statics_, false, position, heading_rad, hits);
  check_world(moving, true, position, heading_rad, hits);
  std::set<Key> now;
  std::vector<Contact> begun;
  for (const Hit& h : hits) {
    const Key key{h.part == BodyPart::kCane, h.moving, h.primitive};
    now.insert(key);
    if (touching_.count(key)) continue;
    const World& w = h.moving ? moving : *statics_;
    const AxisAlignedBox b = bounds_of(w.primitive(h.primitive).shape);
    double lo = body_.step_over_m, hi = body_.legs_top_m;
    if (h.part == BodyPart::kTorso) lo = body_.legs_top_m, hi = body_.head_bottom_m;
    if (h.part == BodyPart::kHead) lo = body_.head_bottom_m, hi = body_.height_m;
    if (h.part == BodyPart::kCane) lo = 0.0, hi = cane_.detect_height_m;
    const double z_lo = std::max(lo, b.min.z() - ground_z_), z_hi = std::min(hi, b.max.z() - ground_z_);
    Contact c;
    c.t_s = t_s;
    c.part = h.part;
    c.moving = h.moving;
    c.primitive = h.primitive;
    c.semantic = w.primitive(h.primitive).surface.semantic;
    c.height_m = 0.5 * (z_lo + z_hi);
    c.where_W = position;
    if (h.part == BodyPart::kCane && cane_touch_ && cane_touch_->primitive == h.primitive && cane_touch_->moving == h.moving) {
      const double a = heading_rad + cane_touch_->bearing_rad;
      c.where_W = position + cane_touch_->distance_m * Vec2(std::cos(a), std::sin(a));
    }
    begun.push_back(c);
  }
  touching_ = std::move(now);
  return begun;
}

}  // namespace navaid::simulation
