#include "navaid/mapping/distance_transform.hpp"

#include <dynamicEDT3D/dynamicEDT3D.h>

#include <algorithm>
#include <cassert>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "navaid/core/enum_names.hpp"

namespace navaid::mapping {

namespace {

constexpr NameTable<DistanceTransformBackend, 2> kBackendNames{{
    {DistanceTransformBackend::kOpenCv, "opencv"},
    {DistanceTransformBackend::kDynamicEdt, "dynamicedt3d"},
}};

void opencv_transform(const ImageU8& mask, ImageF32& out) {
  // OpenCV measures the distance to the nearest zero pixel: zero marks the set cells.
  const cv::Mat set(mask.height, mask.width, CV_8UC1, const_cast<std::uint8_t*>(mask.data()));
  cv::Mat source;
  cv::compare(set, 0, source, cv::CMP_EQ);
  cv::Mat dist(mask.height, mask.width, CV_32FC1, out.data());
  cv::distanceTransform(source, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  assert(dist.data == reinterpret_cast<uchar*>(out.data()));
}

void dynamic_edt_transform(const ImageU8& mask, ImageF32& out) {
  // A one-layer 3D map; the squared range bound exceeds the grid's diagonal, so nothing saturates.
  const int max_sq = mask.width * mask.width + mask.height * mask.height + 1;
  DynamicEDT3D edt(max_sq);
  edt.initializeEmpty(mask.width, mask.height, 1, true);
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      if (mask.at(x, y) != 0) edt.occupyCell(x, y, 0);
    }
  }
  edt.update(true);
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) out.at(x, y) = edt.getDistance(x, y, 0);
  }
}

}  // namespace

std::string to_string(DistanceTransformBackend backend) {
  // An out-of-range value has always printed as the second backend.
  return std::string(enum_name(kBackendNames, backend, "dynamicedt3d"));
}

std::optional<DistanceTransformBackend> distance_transform_backend_from_string(std::string_view name) {
  return enum_value(kBackendNames, name);
}

void distance_transform(const ImageU8& mask, DistanceTransformBackend backend, ImageF32& out) {
  assert(mask.channels == 1);
  if (out.width != mask.width || out.height != mask.height || out.channels != 1) {
    out = ImageF32(mask.width, mask.height, 1);
  }
  if (std::none_of(mask.pixels.begin(), mask.pixels.end(), [](std::uint8_t v) { return v != 0; })) {
    std::fill(out.pixels.begin(), out.pixels.end(), std::numeric_limits<float>::infinity());
    return;
  }
  if (backend == DistanceTransformBackend::kOpenCv) {
    opencv_transform(mask, out);
  } else {
    dynamic_edt_transform(mask, out);
  }
}

}  // namespace navaid::mapping
