// OpenStreetMap input (planning/osm_foot_graph.cpp, libosmium): the first byte picks the file kind
// (.osm XML, .osm.pbf, .osm.gz, .osm.bz2), the rest is the file.
#include "fuzz_support.hpp"
#include "navaid/planning/osm_foot_graph.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  if (size == 0) return 0;
  static const char* const kNames[] = {"map.osm", "map.osm.pbf", "map.osm.gz", "map.osm.bz2"};
  const auto file = fuzz::fresh_scratch_dir() / kNames[data[0] % 4];
  fuzz::write_file(file, fuzz::as_text(data + 1, size - 1));
  fuzz::expect_clear_errors("load_osm_foot_graph", [&] { (void)planning::load_osm_foot_graph(file); });
  return 0;
}
