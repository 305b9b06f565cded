#pragma once
// AprilTag images drawn from the tag family's code bits (Debian's libapriltag holds the codes;
// thirdparty-notes/visp.md), for tests, benchmarks and simulated target objects. No image files
// and no downloads: the pattern of tag `id` is built from the family's code word and bit layout.
//
// Tag geometry (tag36h11): a total_width x total_width grid of cells (10 x 10), the outer ring
// white, the black border square of width_at_border cells (8 x 8) inside it and the 6 x 6 data
// bits inside that (bit i of the code, most significant first, white when set, at cell
// (bit_x[i], bit_y[i]) of the black square). The tag's size is the side of the black square.
#include <string_view>

#include "navaid/core/camera.hpp"
#include "navaid/core/geometry.hpp"
#include "navaid/core/image.hpp"

namespace navaid::simulation {

struct AprilTagFamilyInfo {
  int ncodes = 0;
  int total_width = 0;      ///< cells across the whole pattern, white ring included
  int width_at_border = 0;  ///< cells across the black square
};

/// Known families: "36h11", "25h9", "16h5". navaid::Error for others.
AprilTagFamilyInfo apriltag_family_info(std::string_view family);

/// The pattern of tag `id`, one pixel per cell (total_width x total_width), 0 black / 255 white.
/// navaid::Error for an unknown family or id out of range.
ImageU8 apriltag_cells(std::string_view family, int id);

/// Draws the tag (cells from apriltag_cells) on a plane seen by the camera: the tag frame has its
/// origin at the tag centre, x to the right and y down across the printed face, z into the face
/// (a tag straight ahead of the camera, facing it, has T_C_tag = [I | (0, 0, d)]). `tag_size_m`
/// is the black square's side; the white ring is drawn around it. Each pixel averages
/// supersample^2 rays. When `depth` is given (same size) the covered pixels get the plane's depth
/// along the optical axis. Pixels whose rays miss the pattern are left as they are.
void draw_apriltag(ImageU8& image, const CameraModel& camera, const SE3& T_C_tag, double tag_size_m,
                   const ImageU8& cells, int width_at_border, int supersample = 4, ImageF32* depth = nullptr);

}  // namespace navaid::simulation
