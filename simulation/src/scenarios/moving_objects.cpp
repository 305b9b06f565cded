// People and vehicles moving along polylines at constant speed.
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/scenario.hpp"
#include "scenarios/builders.hpp"

namespace navaid::simulation {

namespace {

struct Locus {
  Vec2 position;
  Vec2 heading;
};

Locus locate(const MovingObject& m, double t_s) {
  if (m.path.empty()) throw Error("MovingObject: empty path");
  if (!(m.speed_mps > 0.0) || !std::isfinite(m.speed_mps)) throw Error("MovingObject: speed must be finite and > 0");
  const std::size_t n = m.path.size();
  const std::size_t segments = m.loop ? n : n - 1;
  // Segment i runs from path[i] to path[(i + 1) % n]; zero-length segments are skipped.
  auto seg = [&](std::size_t i) { return std::make_pair(m.path[i], m.path[(i + 1) % n]); };
  double total = 0.0;
  Vec2 first_heading = Vec2::UnitX(), last_heading = Vec2::UnitX();
  bool have_first = false;
  for (std::size_t i = 0; i < segments; ++i) {
    const auto [a, b] = seg(i);
    const double len = (b - a).norm();
    total += len;
    if (len > 0.0) {
      last_heading = (b - a) / len;
      if (!have_first) first_heading = last_heading;
      have_first = true;
    }
  }
  if (total <= 0.0) return {m.path.front(), Vec2::UnitX()};
  double d = m.speed_mps * (t_s - m.start_s);
  if (d <= 0.0) return {m.path.front(), first_heading};
  if (m.loop) {
    d = std::fmod(d, total);
  } else if (d >= total) {
    return {m.path.back(), last_heading};
  }
  for (std::size_t i = 0; i < segments; ++i) {
    const auto [a, b] = seg(i);
    const double len = (b - a).norm();
    if (len > 0.0 && d <= len) return {a + (d / len) * (b - a), (b - a) / len};
    d -= len;
  }
  return {m.loop ? m.path.front() : m.path.back(), last_heading};  // rounding at the very end
}

}  // namespace

Vec2 moving_position(const MovingObject& m, double t_s) { return locate(m, t_s).position; }

Vec2 moving_heading(const MovingObject& m, double t_s) { return locate(m, t_s).heading; }

World moving_world(const std::vector<MovingObject>& objects, double t_s) {
  World w;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const MovingObject& m = objects[i];
    const Locus l = locate(m, t_s);
    // Texture seeds depend on the object only, so its appearance is the same at every time.
    const auto seed = static_cast<std::uint32_t>(900001u + 16u * i);
    if (m.kind == MovingKind::kPerson) {
      scenarios::add_person_shape(w, l.position, 0.0, m.radius_m, m.height_m, seed);
    } else {
      scenarios::add_car_shape(w, l.position, 0.0, std::atan2(l.heading.y(), l.heading.x()), m.radius_m, m.height_m, seed);
    }
  }
  return w;
}

}  // namespace navaid::simulation
