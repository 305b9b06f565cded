#pragma once
// Checks that a room's declared configuration keys (ConfigSchema) are the keys its read functions
// read, with the same defaults: every key read from an empty Config is declared, and every
// declared key with a default is read and hands out the declared default.
#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/config_schema.hpp"

namespace navaid::testing {

/// `read` reads a room's options from the Config it is given. `conditional` names declared keys
/// that the read does not reach from an empty Config (read only when another key enables them).
inline void expect_schema_matches_reads(const ConfigSchema& schema, const std::function<void(const Config&)>& read,
                                        const std::set<std::string>& conditional = {}) {
  const Config empty;
  ConfigSchema handed_out;
  {
    const ConfigReads reads(empty);
    read(empty);
    handed_out = reads.defaults();
  }
  // The defaults handed out, as a run folder's config.yaml writes them.
  const Config used = Config::parse(empty.dump(handed_out), "<defaults read>");
  EXPECT_NO_THROW(used.reject_unknown_keys(schema)) << "a key is read but not declared";
  for (const auto& key : schema.keys()) {
    if (key.is_map || key.no_default || key.type == "numbers" || conditional.count(key.name)) continue;
    ASSERT_TRUE(used.has(key.name)) << key.name << " is declared with a default but not read from an empty config";
    if (key.list) {
      EXPECT_EQ(used.get_strings(key.name, {}), key.defaults) << key.name;
    } else {
      EXPECT_EQ(used.get_string(key.name), key.defaults.front()) << key.name << ": declared default differs from the one read";
    }
  }
}

}  // namespace navaid::testing
