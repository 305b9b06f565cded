#pragma once
// Private to navaid_io: ROS image messages (raw and compressed) to navaid images. Intensity keeps
// grey as one channel and colour as RGB; depth becomes 16-bit millimetres (the navaid format's
// unit, REP 118's for 16UC1), 0 = invalid. `where` names bag, topic and message in errors.
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <string>

#include "navaid/core/image.hpp"

namespace navaid::io::detail {

enum class RosImageKind { kIntensity, kDepth, kUnsupported };

/// sensor_msgs/Image encodings: mono8, rgb8, bgr8, rgba8, bgra8 -> intensity; 16UC1, mono16,
/// 32FC1 -> depth.
RosImageKind raw_image_kind(const std::string& encoding);
/// CompressedImage formats: "...compressedDepth..." or a 16-bit source ("16UC1; png compressed")
/// -> depth; jpeg / png of 8-bit images -> intensity; anything else (rvl, unknown) unsupported.
RosImageKind compressed_image_kind(const std::string& format);

ImageU8 decode_intensity(const sensor_msgs::Image& msg, const std::string& where);
ImageU8 decode_intensity(const sensor_msgs::CompressedImage& msg, const std::string& where);

struct DepthMillimetres {
  ImageU16 image;
  std::size_t dropped = 0;  ///< valid-looking pixels that a 16-bit millimetre image cannot hold (> 65.535 m)
};
DepthMillimetres decode_depth(const sensor_msgs::Image& msg, const std::string& where);
DepthMillimetres decode_depth(const sensor_msgs::CompressedImage& msg, const std::string& where);

}  // namespace navaid::io::detail
