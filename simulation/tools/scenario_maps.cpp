// Writes the top-view map of every scenario as <out_dir>/scenario-<name>.png (~600 px wide):
// static world, walked path (blue, start green, goal red), moving people/vehicles' paths
// (dashed magenta) and a scale bar. Usage: navaid_scenario_maps <out_dir> [name ...]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "navaid/io/image_io.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/top_view.hpp"

int main(int argc, char** argv) {
  using namespace navaid::simulation;
  if (argc < 2 || std::string(argv[1]) == "--help") {
    std::fprintf(stderr, "usage: %s <out_dir> [scenario ...]\n", argv[0]);
    return argc < 2 ? 2 : 0;
  }
  try {
    const std::filesystem::path out = argv[1];
    std::filesystem::create_directories(out);
    std::vector<std::string> names(argv + 2, argv + argc);
    if (names.empty()) names = scenario_names();
    for (const std::string& name : names) {
      const Scenario s = make_scenario(name);
      const RayCaster caster(s.world);
      const TopViewOptions o = scenario_map_options(s, 600.0);
      const TopView v = render_top_view(caster, o);
      const std::string file = (out / ("scenario-" + name + ".png")).string();
      navaid::io::write_png(file, v.image, 9);
      std::printf("%s: %d x %d px, %.3f m/px, path %.1f m\n", file.c_str(), v.image.width, v.image.height,
                  v.metres_per_pixel, polyline_length(s.path));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navaid_scenario_maps: %s\n", e.what());
    return 1;
  }
  return 0;
}
