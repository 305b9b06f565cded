#include "navaid/simulation/ray_caster.hpp"

#include <cmath>
#include <string>

#include <embree3/rtcore.h>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {
constexpr unsigned kInvalidId = ~0u;  // RTC_INVALID_GEOMETRY_ID without its C-style cast
}  // namespace

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

RayCaster::RayCaster(World world, const Tessellation& tess)
    : world_(std::move(world)), mesh_(world_.triangulate(tess)), impl_(std::make_unique<Impl>()) {
  triangle_normals_.reserve(mesh_.triangles.size());
  for (const auto& t : mesh_.triangles) {
    const Vec3 n = (mesh_.vertices[t[1]] - mesh_.vertices[t[0]]).cross(mesh_.vertices[t[2]] - mesh_.vertices[t[0]]);
    const double len = n.norm();
    triangle_normals_.push_back(len > 0.0 ? Vec3(n / len) : Vec3::Zero());
  }

  // One thread: deterministic and within the single-thread budget of the benchmarks.
  impl_->device = rtcNewDevice("threads=1");
  if (impl_->device == nullptr) throw Error("RayCaster: rtcNewDevice failed (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  if (!mesh_.triangles.empty()) {
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh_.vertices.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), mesh_.triangles.size()));
    if (vb == nullptr || ib == nullptr) {
      rtcReleaseGeometry(geom);
      throw Error("RayCaster: Embree buffer allocation failed");
    }
    for (std::size_t i = 0; i < mesh_.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) vb[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(mesh_.vertices[i][k]);
    for (std::size_t i = 0; i < mesh_.triangles.size(); ++i)
      for (std::size_t k = 0; k < 3; ++k) ib[3 * i + k] = mesh_.triangles[i][k];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(impl_->scene);
  const RTCError err = rtcGetDeviceError(impl_->device);
  if (err != RTC_ERROR_NONE) throw Error("RayCaster: Embree scene build failed (error " + std::to_string(err) + ")");
}

RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&&) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&&) noexcept = default;

std::optional<Hit> RayCaster::cast(const Vec3& origin, const Vec3& dir, double t_max, double t_min) const {
  return cast_impl(origin, dir, t_max, t_min, false);
}

void RayCaster::cast_batch(const Vec3& origin, const std::vector<Vec3>& dirs, std::vector<std::optional<Hit>>& hits,
                           double t_max, double t_min) const {
  hits.resize(dirs.size());
  for (std::size_t i = 0; i < dirs.size(); ++i) hits[i] = cast_impl(origin, dirs[i], t_max, t_min, true);
}

std::optional<Hit> RayCaster::cast_impl(const Vec3& origin, const Vec3& dir, double t_max, double t_min,
                                        bool coherent) const {
  if (mesh_.triangles.empty() || !(t_max >= t_min)) return std::nullopt;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(origin.x());
  rh.ray.org_y = static_cast<float>(origin.y());
  rh.ray.org_z = static_cast<float>(origin.z());
  rh.ray.dir_x = static_cast<float>(dir.x());
  rh.ray.dir_y = static_cast<float>(dir.y());
  rh.ray.dir_z = static_cast<float>(dir.z());
  // The float ray is widened slightly; the exact [t_min, t_max] test is done in double below.
  rh.ray.tnear = static_cast<float>(std::max(0.0, t_min * (1.0 - 1e-5)));
  rh.ray.tfar = std::isfinite(t_max) ? static_cast<float>(t_max * (1.0 + 1e-5) + 1e-6) : std::numeric_limits<float>::infinity();
  rh.ray.time = 0.0f;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = kInvalidId;
  rh.hit.primID = kInvalidId;
  rh.hit.instID[0] = kInvalidId;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == kInvalidId) return std::nullopt;

  Hit hit;
  hit.triangle = rh.hit.primID;
  const auto& tri = mesh_.triangles[hit.triangle];
  hit.normal = triangle_normals_[hit.triangle];
  // Refine the distance in double on the triangle's plane (Embree works in float).
  double t = static_cast<double>(rh.ray.tfar);
  const double denom = hit.normal.dot(dir);
  if (std::abs(denom) > 1e-9) {
    const double t_plane = hit.normal.dot(mesh_.vertices[tri[0]] - origin) / denom;
    if (std::abs(t_plane - t) <= 1e-3 * std::max(1.0, t)) t = t_plane;
  }
  if (t < t_min || t > t_max) return std::nullopt;
  hit.distance = t;
  hit.point = origin + t * dir;
  hit.primitive = mesh_.triangle_primitive[hit.triangle];
  hit.semantic = world_.primitives()[hit.primitive].surface.semantic;
  return hit;
}

}  // namespace navaid::simulation
