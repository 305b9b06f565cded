// map_server maps (io/occupancy_map_file.cpp): the YAML and the PGM/PNG image it names, packed.
#include "fuzz_support.hpp"
#include "navaid/io/occupancy_map_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto& dir = fuzz::fresh_scratch_dir();
  fuzz::unpack_folder(fuzz::as_text(data, size), dir);
  fuzz::expect_clear_errors("read_occupancy_map", [&] { (void)io::read_occupancy_map(dir / "map.yaml"); });
  return 0;
}
