// Configuration YAML with --set overrides (core/config.cpp) and the typed readers that a full-device
// run applies to it. The input is the YAML, then optionally a line "===" and one override per line.
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "navaid/core/config.hpp"
#include "navaid/estimation/config_schema.hpp"
#include "navaid/estimation/estimator_config.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"
#include "navaid/mapping/config_schema.hpp"
#include "navaid/runtime/config_schema.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/mapping/mapper.hpp"
#include "navaid/mapping/segmentation_link.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace navaid;
  const std::string_view text = fuzz::as_text(data, size);
  const std::size_t mark = text.find("\n===\n");
  const std::string yaml(text.substr(0, mark));
  std::vector<std::string> overrides;
  if (mark != std::string_view::npos) {
    std::string_view rest = text.substr(mark + 5);
    while (!rest.empty()) {
      const std::size_t end = rest.find('\n');
      overrides.emplace_back(rest.substr(0, end));
      rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    }
  }
  fuzz::expect_clear_errors("config", [&] {
    const Config config = Config::parse(yaml, "<fuzz>", overrides);
    (void)config.dump();
    (void)estimation::read_estimator_config(config);
    (void)estimation::read_frontend_config(config);
    if (config.has("device.name")) (void)runtime::read_device_spec(config);
    (void)mapping::read_mapper_config(config);
    (void)mapping::read_segmentation_link_config(config);
    config.reject_unknown_keys(estimation::config_schema()
                                   .add(runtime::device_spec_schema())
                                   .add(mapping::mapper_config_schema())
                                   .add(mapping::segmentation_link_config_schema()));
  });
  return 0;
}
