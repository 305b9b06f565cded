#include "ros_bag_images.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "navaid/core/errors.hpp"

namespace navaid::io::detail {
namespace {

bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

// Checks that the message's buffer holds height rows of `step` bytes, each at least width*bpp long.
void check_layout(const sensor_msgs::Image& msg, std::size_t bytes_per_pixel, const std::string& where) {
  if (msg.width == 0 || msg.height == 0) throw IoError(where, "image is empty (" + std::to_string(msg.width) + "x" + std::to_string(msg.height) + ")");
  const std::uint64_t row = static_cast<std::uint64_t>(msg.width) * bytes_per_pixel;
  if (msg.step < row)
    throw IoError(where, "step " + std::to_string(msg.step) + " is shorter than a row of " + std::to_string(msg.width) +
                             " " + msg.encoding + " pixels (" + std::to_string(row) + " bytes)");
  const std::uint64_t need = static_cast<std::uint64_t>(msg.step) * msg.height;
  if (msg.data.size() < need)
    throw IoError(where, "data holds " + std::to_string(msg.data.size()) + " bytes, step x height needs " +
                             std::to_string(need));
}

// Lets OpenCV decode a jpeg / png buffer; IoError when it cannot.
cv::Mat decode_buffer(const std::uint8_t* data, std::size_t size, const std::string& format, const std::string& where) {
  if (size == 0) throw IoError(where, "compressed image (" + format + ") holds no data");
  const cv::Mat buffer(1, static_cast<int>(size), CV_8UC1, const_cast<std::uint8_t*>(data));
  cv::Mat image;
  try {
    image = cv::imdecode(buffer, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw IoError(where, "compressed image (" + format + ") cannot be decoded: " + e.what());
  }
  if (image.empty()) throw IoError(where, "compressed image (" + format + ") cannot be decoded");
  return image;
}

std::uint16_t to_millimetres(double metres, std::size_t& dropped) {
  if (!std::isfinite(metres) || metres <= 0) return 0;
  const double mm = std::round(metres * 1000.0);
  if (mm > 65535.0) {
    ++dropped;
    return 0;
  }
  return static_cast<std::uint16_t>(mm);
}

}  // namespace

RosImageKind raw_image_kind(const std::string& encoding) {
  if (encoding == "mono8" || encoding == "rgb8" || encoding == "bgr8" || encoding == "rgba8" || encoding == "bgra8" ||
      encoding == "8UC1" || encoding == "8UC3")
    return RosImageKind::kIntensity;
  if (encoding == "16UC1" || encoding == "mono16" || encoding == "32FC1") return RosImageKind::kDepth;
  return RosImageKind::kUnsupported;
}

RosImageKind compressed_image_kind(const std::string& format) {
  if (contains(format, "rvl")) return RosImageKind::kUnsupported;
  if (contains(format, "compressedDepth") || contains(format, "16UC1") || contains(format, "mono16") ||
      contains(format, "32FC1"))
    return RosImageKind::kDepth;
  if (contains(format, "jpeg") || contains(format, "jpg") || contains(format, "png")) return RosImageKind::kIntensity;
  return RosImageKind::kUnsupported;
}

ImageU8 decode_intensity(const sensor_msgs::Image& msg, const std::string& where) {
  const std::string& e = msg.encoding;
  const int in_channels = (e == "mono8" || e == "8UC1") ? 1 : (e == "rgba8" || e == "bgra8") ? 4 : 3;
  if (raw_image_kind(e) != RosImageKind::kIntensity)
    throw IoError(where, "encoding '" + e + "' is not an intensity image (mono8, rgb8, bgr8, rgba8, bgra8)");
  check_layout(msg, static_cast<std::size_t>(in_channels), where);
  const bool swap = e == "bgr8" || e == "bgra8" || e == "8UC3";  // 8UC3 is OpenCV's BGR
  const int channels = in_channels == 1 ? 1 : 3;
  ImageU8 out(static_cast<int>(msg.width), static_cast<int>(msg.height), channels);
  for (int y = 0; y < out.height; ++y) {
    const std::uint8_t* row = msg.data.data() + static_cast<std::size_t>(y) * msg.step;
    for (int x = 0; x < out.width; ++x) {
      const std::uint8_t* p = row + static_cast<std::size_t>(x) * in_channels;
      if (channels == 1) {
        out.at(x, y) = p[0];
        continue;
      }
      out.at(x, y, 0) = swap ? p[2] : p[0];
      out.at(x, y, 1) = p[1];
      out.at(x, y, 2) = swap ? p[0] : p[2];
    }
  }
  return out;
}

ImageU8 decode_intensity(const sensor_msgs::CompressedImage& msg, const std::string& where) {
  if (compressed_image_kind(msg.format) != RosImageKind::kIntensity)
    throw IoError(where, "format '" + msg.format + "' is not a jpeg or png intensity image");
  const cv::Mat m = decode_buffer(msg.data.data(), msg.data.size(), msg.format, where);
  if (m.depth() != CV_8U || (m.channels() != 1 && m.channels() != 3 && m.channels() != 4))
    throw IoError(where, "compressed image decodes to " + std::to_string(m.channels()) + " channel(s) of " +
                             (m.depth() == CV_16U ? "16" : "non-8") + "-bit pixels, not an 8-bit grey or colour image");
  ImageU8 out(m.cols, m.rows, m.channels() == 1 ? 1 : 3);
  for (int y = 0; y < m.rows; ++y) {
    const std::uint8_t* row = m.ptr<std::uint8_t>(y);
    for (int x = 0; x < m.cols; ++x) {
      const std::uint8_t* p = row + static_cast<std::size_t>(x) * m.channels();
      if (out.channels == 1) {
        out.at(x, y) = p[0];
        continue;
      }
      out.at(x, y, 0) = p[2];  // OpenCV decodes colour as BGR(A)
      out.at(x, y, 1) = p[1];
      out.at(x, y, 2) = p[0];
    }
  }
  return out;
}

DepthMillimetres decode_depth(const sensor_msgs::Image& msg, const std::string& where) {
  const std::string& e = msg.encoding;
  if (raw_image_kind(e) != RosImageKind::kDepth)
    throw IoError(where, "encoding '" + e + "' is not a depth image (16UC1 or mono16 in millimetres, 32FC1 in metres)");
  const bool is_float = e == "32FC1";
  check_layout(msg, is_float ? 4 : 2, where);
  DepthMillimetres out{ImageU16(static_cast<int>(msg.width), static_cast<int>(msg.height)), 0};
  for (int y = 0; y < out.image.height; ++y) {
    const std::uint8_t* row = msg.data.data() + static_cast<std::size_t>(y) * msg.step;
    for (int x = 0; x < out.image.width; ++x) {
      const std::uint8_t* p = row + static_cast<std::size_t>(x) * (is_float ? 4 : 2);
      std::uint8_t b[4];
      std::memcpy(b, p, is_float ? 4 : 2);
      if (msg.is_bigendian) std::reverse(b, b + (is_float ? 4 : 2));
      if (is_float) {
        float metres = 0;
        std::memcpy(&metres, b, 4);
        out.image.at(x, y) = to_millimetres(metres, out.dropped);
      } else {
        std::uint16_t mm = 0;
        std::memcpy(&mm, b, 2);
        out.image.at(x, y) = mm;
      }
    }
  }
  return out;
}

DepthMillimetres decode_depth(const sensor_msgs::CompressedImage& msg, const std::string& where) {
  if (compressed_image_kind(msg.format) != RosImageKind::kDepth)
    throw IoError(where, "format '" + msg.format + "' is not a compressed depth image (compressedDepth or 16-bit png)");
  const bool depth_transport = contains(msg.format, "compressedDepth");
  // compressed_depth_image_transport puts a 12-byte header before its PNG: the format (int32) and
  // two floats that quantise inverse depth for 32FC1 sources.
  constexpr std::size_t kHeader = 12;
  if (depth_transport && msg.data.size() <= kHeader)
    throw IoError(where, "compressedDepth message holds " + std::to_string(msg.data.size()) + " bytes, less than its header");
  const std::size_t skip = depth_transport ? kHeader : 0;
  const cv::Mat m = decode_buffer(msg.data.data() + skip, msg.data.size() - skip, msg.format, where);
  if (m.depth() != CV_16U || m.channels() != 1)
    throw IoError(where, "compressed depth decodes to " + std::to_string(m.channels()) + " channel(s), not one 16-bit channel");
  DepthMillimetres out{ImageU16(m.cols, m.rows), 0};
  const bool inverse = depth_transport && contains(msg.format, "32FC1");
  float quant_a = 0, quant_b = 0;
  if (inverse) {
    std::memcpy(&quant_a, msg.data.data() + 4, 4);
    std::memcpy(&quant_b, msg.data.data() + 8, 4);
    if (!std::isfinite(quant_a) || !std::isfinite(quant_b) || quant_a == 0)
      throw IoError(where, "compressedDepth header holds no usable inverse-depth quantisation");
  }
  for (int y = 0; y < m.rows; ++y) {
    const std::uint16_t* row = m.ptr<std::uint16_t>(y);
    for (int x = 0; x < m.cols; ++x) {
      if (!inverse) {
        out.image.at(x, y) = row[x];
        continue;
      }
      // Inverse depth q = a / d + b, so d = a / (q - b); 0 marks no measurement.
      const double q = row[x];
      out.image.at(x, y) = q == 0 ? 0 : to_millimetres(quant_a / (q - quant_b), out.dropped);
    }
  }
  return out;
}

}  // namespace navaid::io::detail
