#pragma once
// Euclidean distance transform of a binary grid: for every cell, the distance from its centre to
// the nearest set cell's centre. Two backends, chosen by measurement (thirdparty-notes/opencv.md,
// thirdparty-notes/octomap.md): OpenCV's exact transform (cv::distanceTransform, DIST_L2 with
// DIST_MASK_PRECISE, Felzenszwalb-Huttenlocher) and dynamicEDT3D run on a one-layer map (Lau's
// brushfire, made for incremental updates).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "navaid/core/image.hpp"

namespace navaid::mapping {

enum class DistanceTransformBackend { kOpenCv, kDynamicEdt };

/// "opencv" or "dynamicedt3d" (the config spelling).
std::string to_string(DistanceTransformBackend backend);
/// Inverse of to_string; nullopt for any other name.
std::optional<DistanceTransformBackend> distance_transform_backend_from_string(std::string_view name);

/// Distances [cells] into `out` (resized to the mask's size): 0 on set cells (mask != 0), +inf
/// everywhere when no cell is set. `mask` has one channel.
void distance_transform(const ImageU8& mask, DistanceTransformBackend backend, ImageF32& out);

}  // namespace navaid::mapping
