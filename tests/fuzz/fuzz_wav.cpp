// WAV files (interaction/wav_file.cpp), read back by the speech tools and tests.
#include "fuzz_support.hpp"
#include "navaid/interaction/wav_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const auto file = fuzz::fresh_scratch_dir() / "speech.wav";
  fuzz::write_file(file, fuzz::as_text(data, size));
  fuzz::expect_clear_errors("read_wav", [&] { (void)interaction::read_wav(file); });
  return 0;
}
