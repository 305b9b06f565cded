#include "navaid/core/geodesy.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>

namespace navaid {

struct LocalEnuFrame::Impl {
  GeographicLib::LocalCartesian cartesian;
};

LocalEnuFrame::LocalEnuFrame(const GeodeticOrigin& origin)
    : origin_(origin),
      impl_(std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(
          origin.latitude_deg, origin.longitude_deg, origin.height_m, GeographicLib::Geocentric::WGS84())})) {}

LocalEnuFrame::~LocalEnuFrame() = default;
LocalEnuFrame::LocalEnuFrame(const LocalEnuFrame& o) : origin_(o.origin_), impl_(std::make_unique<Impl>(*o.impl_)) {}
LocalEnuFrame& LocalEnuFrame::operator=(const LocalEnuFrame& o) {
  if (this != &o) {
    origin_ = o.origin_;
    impl_ = std::make_unique<Impl>(*o.impl_);
  }
  return *this;
}

Vec3 LocalEnuFrame::to_enu(double latitude_deg, double longitude_deg, double height_m) const {
  Vec3 enu;
  impl_->cartesian.Forward(latitude_deg, longitude_deg, height_m, enu.x(), enu.y(), enu.z());
  return enu;
}

Vec3 LocalEnuFrame::to_geodetic(const Vec3& enu) const {
  Vec3 geo;
  impl_->cartesian.Reverse(enu.x(), enu.y(), enu.z(), geo.x(), geo.y(), geo.z());
  return geo;
}

std::optional<double> ellipsoidal_height_m(const GpsFix& fix) {
  if (fix.mode != GpsFixMode::k3D || !std::isfinite(fix.altitude_m)) return std::nullopt;
  return fix.altitude_m + (std::isfinite(fix.geoid_separation_m) ? fix.geoid_separation_m : 0.0);
}

std::optional<GeodeticOrigin> origin_from_fixes(const std::vector<GpsFix>& fixes) {
  for (const auto& fix : fixes)
    if (const auto h = ellipsoidal_height_m(fix)) return GeodeticOrigin{fix.latitude_deg, fix.longitude_deg, *h};
  for (const auto& fix : fixes)
    if (fix.mode != GpsFixMode::kNoFix) return GeodeticOrigin{fix.latitude_deg, fix.longitude_deg, 0.0};
  return std::nullopt;
}

GeodesicLine geodesic_inverse(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg) {
  GeodesicLine line;
  double azimuth2 = 0;
  GeographicLib::Geodesic::WGS84().Inverse(lat1_deg, lon1_deg, lat2_deg, lon2_deg, line.distance_m,
                                           line.azimuth_deg, azimuth2);
  return line;
}

}  // namespace navaid
