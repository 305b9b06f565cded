#pragma once
// Frame image files: loading the lazily referenced images of an RgbdFrame, and PNG writers.
// Every failure is an IoError naming the image file. OpenCV stays inside io/src.
#include <string>

#include "navaid/core/image.hpp"
#include "navaid/core/messages.hpp"

namespace navaid::io {

/// A depth image whose valid pixels are all nearer than this is rejected as "wrong units": no
/// depth camera measures a whole frame below 5 cm, but metres stored as integers in a millimetre
/// PNG look exactly like that (a 3 m wall becomes 3 mm).
constexpr double kMinPlausibleMaxDepthM = 0.05;

/// Fills frame.intensity, frame.depth, frame.labels and frame.label_confidence from the non-empty
/// *_path members (members whose path is empty are left untouched). Depth becomes metres: raw value
/// times frame.depth_png_scale_m, with 0 kept as 0 (invalid); confidence becomes value / 255. A
/// confidence image whose size differs from the labels' is an IoError naming the confidence file.
void load_frame_images(RgbdFrame& frame);
/// Frees the pixel buffers (paths are kept), e.g. after a frame has been consumed.
void release_frame_images(RgbdFrame& frame);

/// Any 8-bit image OpenCV decodes: grey stays 1 channel, colour becomes RGB (3 channels, alpha
/// dropped). 16-bit intensity images are rejected rather than silently rescaled.
ImageU8 read_intensity_image(const std::string& path);
/// Grey (one channel) from a grey or RGB image (ITU-R BT.601 weights); IoError naming `file` for
/// any other channel count.
ImageU8 to_gray(const ImageU8& image, const std::string& file);
/// 8-bit single-channel PNG of class ids.
ImageU8 read_label_image(const std::string& path);
/// 8-bit single-channel label-confidence PNG, raw units (round(255 p)).
ImageU8 read_confidence_png_raw(const std::string& path);
/// 8-bit single-channel label-confidence PNG as probabilities (value / 255).
ImageF32 read_confidence_png(const std::string& path);
/// Probabilities to confidence PNG units, round(255 p). Throws IoError naming `path` (the file
/// being written) and the pixel for a value outside [0, 1] or NaN, and for more than one channel.
ImageU8 confidence_to_png_units(const ImageF32& probability, const std::string& path);

/// 16-bit single-channel depth PNG, raw units; checks the units (see check_depth_units).
ImageU16 read_depth_png_raw(const std::string& path, double scale_m);
/// 16-bit single-channel depth PNG in metres (raw * scale_m; 0 = invalid).
ImageF32 read_depth_png(const std::string& path, double scale_m);

/// Throws IoError (naming `path`) when the image has valid pixels and all of them are nearer than
/// kMinPlausibleMaxDepthM at `scale_m` metres per unit: metres stored where millimetres belong.
void check_depth_units(const ImageU16& raw, double scale_m, const std::string& path);

/// Metric depth to PNG units (round(d / scale_m)); 0 stays 0. Throws IoError naming `path` (the
/// file being written) for NaN, Inf or negative depth and for depth beyond 65535 units.
ImageU16 depth_to_png_units(const ImageF32& depth_m, double scale_m, const std::string& path);
/// Re-expresses raw depth units: round(raw * from_scale_m / to_scale_m); exact when the scales
/// are equal. Throws IoError naming `path` when a value leaves the 16-bit range.
ImageU16 convert_depth_units(const ImageU16& raw, double from_scale_m, double to_scale_m,
                             const std::string& path);

/// PNG writers: 1-channel grey or 3-channel RGB (8-bit), 1-channel 16-bit. `compression` is the
/// zlib level 0-9; the same pixels and level always give the same bytes. The parent folder must
/// exist.
void write_png(const std::string& path, const ImageU8& image, int compression = 3);
void write_png(const std::string& path, const ImageU16& image, int compression = 3);

}  // namespace navaid::io
