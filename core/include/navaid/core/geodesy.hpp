#pragma once
// Geodesy on the WGS84 ellipsoid through GeographicLib (never hand-written, DESIGN.md §4).
// Geodetic angles are in degrees, as GeographicLib and every receiver use them.
#include <memory>
#include <optional>
#include <vector>

#include "navaid/core/calibration.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/messages.hpp"

namespace navaid {

/// East-north-up frame tangent to the ellipsoid at a geodetic origin.
class LocalEnuFrame {
 public:
  explicit LocalEnuFrame(const GeodeticOrigin& origin);
  ~LocalEnuFrame();
  LocalEnuFrame(const LocalEnuFrame&);
  LocalEnuFrame& operator=(const LocalEnuFrame&);

  const GeodeticOrigin& origin() const { return origin_; }
  /// Geodetic (degrees, ellipsoidal height in metres) to ENU metres.
  Vec3 to_enu(double latitude_deg, double longitude_deg, double height_m) const;
  /// ENU metres to geodetic: returns (latitude_deg, longitude_deg, height_m).
  Vec3 to_geodetic(const Vec3& enu) const;

 private:
  struct Impl;
  GeodeticOrigin origin_;
  std::unique_ptr<Impl> impl_;
};

/// Result of the inverse geodesic problem between two points.
struct GeodesicLine {
  double distance_m = 0;   ///< along the ellipsoid
  double azimuth_deg = 0;  ///< at the first point, clockwise from north
};

/// Height above the ellipsoid (MSL altitude + geoid separation); nullopt without a measured
/// altitude (no fix, 2D fix). A missing geoid separation counts as 0 (receivers that omit it
/// usually report ellipsoidal height as altitude).
std::optional<double> ellipsoidal_height_m(const GpsFix& fix);

/// An ENU origin for fixes that come without one: the first 3D fix with a measured height, else
/// the first located fix at height 0; nullopt when no fix has a position.
std::optional<GeodeticOrigin> origin_from_fixes(const std::vector<GpsFix>& fixes);

GeodesicLine geodesic_inverse(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg);

}  // namespace navaid
