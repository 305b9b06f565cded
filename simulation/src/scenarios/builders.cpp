#include "scenarios/builders.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/apriltag_image.hpp"

namespace navaid::simulation::scenarios {

namespace {
using C = SemanticClass;
Quat yaw_quat(double yaw) { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }
}  // namespace

Surface SceneBuilder::surface(SemanticClass c, double texture_scale) {
  Surface s;
  s.semantic = c;
  s.texture_seed = static_cast<std::uint32_t>(world_.size() * 2654435761u + 17u);
  s.texture_scale = texture_scale;
  s.albedo = rng_.uniform(0.35, 0.85);
  return s;
}

std::uint32_t SceneBuilder::box(const Vec3& lo, const Vec3& hi, SemanticClass c, double texture_scale) {
  return world_.add(Box{SE3(Quat::Identity(), 0.5 * (lo + hi)), 0.5 * (hi - lo)}, surface(c, texture_scale));
}

std::uint32_t SceneBuilder::oriented_box(const Vec3& center, const Vec3& half, double yaw, SemanticClass c,
                                         double texture_scale) {
  return world_.add(Box{SE3(yaw_quat(yaw), center), half}, surface(c, texture_scale));
}

std::uint32_t SceneBuilder::horizontal_patch(const Vec2& lo, const Vec2& hi, double z, SemanticClass c,
                                             double texture_scale) {
  const Vec2 mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  return world_.add(PlanePatch{SE3(Quat::Identity(), Vec3(mid.x(), mid.y(), z)), half.x(), half.y()},
                    surface(c, texture_scale));
}

std::uint32_t SceneBuilder::cylinder(const Vec2& xy, double z0, double radius, double height, SemanticClass c,
                                     double texture_scale) {
  return world_.add(VerticalCylinder{Vec3(xy.x(), xy.y(), z0), radius, height}, surface(c, texture_scale));
}

std::uint32_t SceneBuilder::sidewalk(const Vec2& lo, const Vec2& hi, double z_top, double depth) {
  return box(Vec3(lo.x(), lo.y(), z_top - depth), Vec3(hi.x(), hi.y(), z_top), C::kSidewalk, 0.25);
}

std::uint32_t SceneBuilder::curb(const Vec2& a, const Vec2& b, double z_bottom, double z_top) {
  const double w = 0.075;
  const Vec2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  const bool along_x = std::abs(b.x() - a.x()) >= std::abs(b.y() - a.y());
  const Vec2 pad = along_x ? Vec2(0.0, w) : Vec2(w, 0.0);
  return box(Vec3(lo.x() - pad.x(), lo.y() - pad.y(), z_bottom), Vec3(hi.x() + pad.x(), hi.y() + pad.y(), z_top + 0.01),
             C::kCurb, 0.1);
}

std::uint32_t SceneBuilder::tactile_strip(const Vec2& a, const Vec2& b, double z) {
  const Vec2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  const bool along_x = std::abs(b.x() - a.x()) >= std::abs(b.y() - a.y());
  const Vec2 pad = along_x ? Vec2(0.0, 0.15) : Vec2(0.15, 0.0);
  return horizontal_patch(lo - pad, hi + pad, z + 0.005, C::kTactilePaving, 0.05);
}

void SceneBuilder::tree(const Vec2& xy, double z0, double crown_bottom_z, double crown_radius,
                        const std::vector<Vec2>& branch_reach, std::vector<std::uint32_t>* branches) {
  const double trunk_r = rng_.uniform(0.12, 0.2);
  const double crown_rz = 0.75 * crown_radius;
  const double crown_center = crown_bottom_z + crown_rz;
  cylinder(xy, z0, trunk_r, crown_center - z0, C::kTreeTrunk, 0.08);
  // The crown's surface (its albedo draw) before its yaw: the order of record (random_draws.hpp).
  const Surface crown_surface = surface(C::kVegetation, 0.15);
  const double crown_yaw = rng_.uniform(0.0, M_PI);
  world_.add(Ellipsoid{SE3(yaw_quat(crown_yaw), Vec3(xy.x(), xy.y(), crown_center)),
                       Vec3(crown_radius, 0.9 * crown_radius, crown_rz)},
             crown_surface);
  for (const Vec2& reach : branch_reach) {
    // A branch is a thin ellipsoid from the trunk outwards, drooping slightly at its tip.
    const double len = reach.norm();
    const double z = z0 + rng_.uniform(1.5, 1.75);
    const Vec2 mid = xy + 0.5 * reach;
    const Quat q = yaw_quat(std::atan2(reach.y(), reach.x())) * Quat(Eigen::AngleAxisd(0.08, Vec3::UnitY()));
    const std::uint32_t i =
        world_.add(Ellipsoid{SE3(q, Vec3(mid.x(), mid.y(), z)), Vec3(0.5 * len, 0.25, 0.12)}, surface(C::kVegetation, 0.1));
    if (branches) branches->push_back(i);
  }
}

void SceneBuilder::pole(const Vec2& xy, double z0, double height, bool with_sign, double sign_normal_yaw) {
  cylinder(xy, z0, 0.06, height, C::kPole, 0.05);
  if (with_sign)
    oriented_box(Vec3(xy.x(), xy.y(), z0 + height - 0.4), Vec3(0.02, 0.3, 0.3), sign_normal_yaw, C::kTrafficSign, 0.05);
}

void SceneBuilder::bench(const Vec2& xy, double z0, double yaw) {
  oriented_box(Vec3(xy.x(), xy.y(), z0 + 0.225), Vec3(0.9, 0.22, 0.225), yaw, C::kBench, 0.08);
}

void SceneBuilder::car(const Vec2& xy, double z0, double yaw) {
  add_car_shape(world_, xy, z0, yaw, 0.9, 1.5, static_cast<std::uint32_t>(world_.size() * 7919u + 3u));
}

void SceneBuilder::person(const Vec2& xy, double z0, double radius, double height) {
  add_person_shape(world_, xy, z0, radius, height, static_cast<std::uint32_t>(world_.size() * 7919u + 5u));
}

void SceneBuilder::bus_stop(double x0, double x1, double y_back, double y_front, double z0) {
  const double s = y_front > y_back ? 1.0 : -1.0;  // towards the road
  box(Vec3(x0, std::min(y_back, y_back + s * 0.05), z0), Vec3(x1, std::max(y_back, y_back + s * 0.05), z0 + 2.3),
      C::kBusStop, 0.1);
  box(Vec3(x0 - 0.2, std::min(y_back, y_front) - 0.1, z0 + 2.4), Vec3(x1 + 0.2, std::max(y_back, y_front) + 0.1, z0 + 2.55),
      C::kBusStop, 0.15);
  for (double x : {x0, x1})
    for (double y : {y_back + s * 0.1, y_front - s * 0.1}) cylinder(Vec2(x, y), z0, 0.05, 2.4, C::kBusStop, 0.05);
  box(Vec3(0.5 * (x0 + x1) - 1.2, std::min(y_back + s * 0.1, y_back + s * 0.5), z0 + 0.4),
      Vec3(0.5 * (x0 + x1) + 1.2, std::max(y_back + s * 0.1, y_back + s * 0.5), z0 + 0.48), C::kBench, 0.08);
}

void SceneBuilder::landmark(const Vec2& xy, double z0, double width, double yaw) {
  const Vec2 along(-std::sin(yaw), std::cos(yaw));
  for (double side : {-0.5, 0.5}) cylinder(xy + side * width * along, z0, 0.08, 2.8, C::kPole, 0.05);
  oriented_box(Vec3(xy.x(), xy.y(), z0 + 2.1), Vec3(0.05, 0.5 * width, 0.6), yaw, C::kTrafficSign, 0.05);
}

void SceneBuilder::chair(const Vec2& xy, double z0, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  oriented_box(Vec3(xy.x(), xy.y(), z0 + 0.44), Vec3(0.22, 0.22, 0.03), yaw, C::kChair, 0.05);
  const Vec2 back = xy - 0.2 * Vec2(c, s);
  oriented_box(Vec3(back.x(), back.y(), z0 + 0.68), Vec3(0.02, 0.22, 0.22), yaw, C::kChair, 0.05);
  for (double u : {-0.18, 0.18})
    for (double v : {-0.18, 0.18}) {
      const Vec2 leg = xy + Vec2(c * u - s * v, s * u + c * v);
      oriented_box(Vec3(leg.x(), leg.y(), z0 + 0.205), Vec3(0.02, 0.02, 0.205), yaw, C::kChair, 0.05);
    }
}

TargetObject SceneBuilder::tagged_box(const std::string& name, const Vec2& xy, double z0, const Vec3& half, double yaw,
                                      const std::string& family, int tag_id, double tag_size_m, int margin_cells) {
  const AprilTagFamilyInfo info = apriltag_family_info(family);
  // The printed card: the pattern (white ring included) plus a margin of white cells, as tags are
  // printed with a white border wider than the one-cell ring (the quad detector needs a white
  // frame around the black square where the background is brighter than the card).
  const ImageU8 pattern = apriltag_cells(family, tag_id);
  const int cells_across = pattern.width + 2 * margin_cells;
  auto card_image = std::make_shared<ImageU8>(cells_across, cells_across, 1, std::uint8_t{255});
  for (int y = 0; y < pattern.height; ++y)
    for (int x = 0; x < pattern.width; ++x) card_image->at(x + margin_cells, y + margin_cells) = pattern.at(x, y);
  const double pattern_half = 0.5 * tag_size_m * cells_across / info.width_at_border;
  if (!(tag_size_m > 0.0) || margin_cells < 0 || pattern_half > half.y() || pattern_half > half.z())
    throw Error("tagged_box '" + name + "': the tag pattern (" + std::to_string(2.0 * pattern_half) +
                " m with its margin) does not fit on the box face");
  TargetObject t;
  t.name = name;
  t.center_W = Vec3(xy.x(), xy.y(), z0 + half.z());
  t.half_extents = half;
  t.tag_family = family;
  t.tag_id = tag_id;
  t.tag_size_m = tag_size_m;
  Surface body;
  body.semantic = t.semantic;
  body.texture_seed = static_cast<std::uint32_t>(world_.size() * 2654435761u + 17u);
  body.texture_scale = 0.04;
  body.albedo = 0.55;
  t.primitives.push_back(world_.add(Box{SE3(yaw_quat(yaw), t.center_W), half}, body));
  // The tag: a card 2 mm in front of the +x face, upright (picture rows run down along -z).
  const Vec3 n(std::cos(yaw), std::sin(yaw), 0.0);
  const Vec3 up = Vec3::UnitZ();
  Mat3 R_W_P;
  R_W_P.col(2) = n;
  R_W_P.col(1) = up;
  R_W_P.col(0) = up.cross(n);
  const Vec3 centre = t.center_W + (half.x() + 0.002) * n;
  Surface card;
  card.semantic = t.semantic;
  card.texture_seed = body.texture_seed + 1;
  card.albedo = 0.9;
  t.primitives.push_back(world_.add(PlanePatch{SE3(R_W_P, centre), pattern_half, pattern_half}, card,
                                    std::shared_ptr<const ImageU8>(std::move(card_image))));
  Mat3 R_W_tag;  // x along the picture's columns, y down the rows, z into the face
  R_W_tag.col(0) = R_W_P.col(0);
  R_W_tag.col(1) = -R_W_P.col(1);
  R_W_tag.col(2) = -R_W_P.col(2);
  t.T_W_tag = SE3(R_W_tag, centre);
  return t;
}

void SceneBuilder::table(const Vec2& center, const Vec2& half, double z0, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  oriented_box(Vec3(center.x(), center.y(), z0 + 0.72), Vec3(half.x(), half.y(), 0.02), yaw, C::kTable, 0.06);
  for (double u : {-1.0, 1.0})
    for (double v : {-1.0, 1.0}) {
      const Vec2 off((half.x() - 0.05) * u, (half.y() - 0.05) * v);
      const Vec2 leg = center + Vec2(c * off.x() - s * off.y(), s * off.x() + c * off.y());
      oriented_box(Vec3(leg.x(), leg.y(), z0 + 0.35), Vec3(0.03, 0.03, 0.35), yaw, C::kTable, 0.05);
    }
}

void SceneBuilder::wall(const Vec2& a, const Vec2& b, double thickness, double z0, double height,
                        const std::vector<std::pair<double, double>>& doors, SemanticClass c, double texture_scale) {
  const double length = (b - a).norm();
  const Vec2 dir = (b - a) / length;
  const Vec2 normal(-dir.y(), dir.x());
  auto piece = [&](double s0, double s1, double z_lo, double z_hi, SemanticClass cls) {
    if (s1 - s0 < 1e-6) return;
    const Vec2 p0 = a + s0 * dir - 0.5 * thickness * normal, p1 = a + s1 * dir + 0.5 * thickness * normal;
    box(Vec3(std::min(p0.x(), p1.x()), std::min(p0.y(), p1.y()), z_lo),
        Vec3(std::max(p0.x(), p1.x()), std::max(p0.y(), p1.y()), z_hi), cls, texture_scale);
  };
  std::vector<std::pair<double, double>> sorted = doors;
  std::sort(sorted.begin(), sorted.end());
  double s = 0.0;
  const double door_top = std::min(2.1, height - 0.05);
  for (const auto& [centre, width] : sorted) {
    const double d0 = std::max(s, centre - 0.5 * width), d1 = std::min(length, centre + 0.5 * width);
    piece(s, d0, z0, z0 + height, c);
    piece(d0, d1, z0 + door_top, z0 + height, SemanticClass::kDoor);
    s = d1;
  }
  piece(s, length, z0, z0 + height, c);
}

void SceneBuilder::room_shell(const Vec2& lo, const Vec2& hi, double z0, double ceiling_height, double texture_scale) {
  horizontal_patch(lo, hi, z0, C::kFloor, texture_scale);
  if (ceiling_height > 0.0) {
    const Vec2 mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    // Flipped so that the ceiling faces down into the room.
    world_.add(PlanePatch{SE3(Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX())), Vec3(mid.x(), mid.y(), z0 + ceiling_height)),
                          half.x(), half.y()},
               surface(C::kCeiling, texture_scale));
  }
}

void add_person_shape(World& world, const Vec2& xy, double z0, double radius, double height, std::uint32_t texture_seed) {
  const double head_rz = 0.12;
  const double body_h = height - 2.0 * head_rz;
  world.add(VerticalCylinder{Vec3(xy.x(), xy.y(), z0), radius, body_h},
            Surface{C::kPerson, texture_seed, 0.08, 0.5});
  world.add(Ellipsoid{SE3(Quat::Identity(), Vec3(xy.x(), xy.y(), z0 + body_h + head_rz)), Vec3(0.09, 0.1, head_rz)},
            Surface{C::kPerson, texture_seed + 1u, 0.05, 0.6});
}

void add_car_shape(World& world, const Vec2& xy, double z0, double yaw, double half_width, double height,
                   std::uint32_t texture_seed) {
  const double half_len = 2.4 * half_width;
  const double body_h = 0.6 * height;
  world.add(Box{SE3(yaw_quat(yaw), Vec3(xy.x(), xy.y(), z0 + 0.15 + 0.5 * (body_h - 0.15))),
                Vec3(half_len, half_width, 0.5 * (body_h - 0.15))},
            Surface{C::kCar, texture_seed, 0.2, 0.5});
  const Vec2 back = xy - 0.15 * half_len * Vec2(std::cos(yaw), std::sin(yaw));
  world.add(Box{SE3(yaw_quat(yaw), Vec3(back.x(), back.y(), z0 + body_h + 0.5 * (height - body_h))),
                Vec3(0.55 * half_len, 0.9 * half_width, 0.5 * (height - body_h))},
            Surface{C::kCar, texture_seed + 1u, 0.15, 0.4});
}

MovingObject looping_person(std::vector<Vec2> path, double speed_mps, double start_s, double height_m) {
  MovingObject m;
  m.path = std::move(path);
  m.speed_mps = speed_mps;
  m.start_s = start_s;
  m.loop = true;
  m.height_m = height_m;
  return m;
}

MovingObject looping_car(std::vector<Vec2> path, double speed_mps, double start_s) {
  MovingObject m = looping_person(std::move(path), speed_mps, start_s, 1.5);
  m.kind = MovingKind::kCar;
  m.radius_m = 0.9;  // half width of a small car
  return m;
}

}  // namespace navaid::simulation::scenarios
