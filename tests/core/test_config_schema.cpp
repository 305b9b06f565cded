// Declared configuration keys: get() validates as the Config getters do (same messages), the
// schema finds unknown keys, lists and documents every key, and a loaded Config can be read from
// several threads at once.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>

#include "navaid/core/config.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/config_schema.hpp"
#include "navaid/core/errors.hpp"
#include "test_support.hpp"

using navaid::Config;
using navaid::ConfigError;
using navaid::ConfigKey;
using navaid::ConfigMapKey;
using navaid::ConfigSchema;

namespace {

template <typename F>
std::string schema_config_error(F&& f) {
  return navaid::testing::error_message<ConfigError>(std::forward<F>(f));
}

const ConfigKey<double> kRate{"sensor.imu.rate", 200.0, {1.0, 1000.0}, "IMU rate in Hz"};
const ConfigKey<double> kBias{"sensor.imu.bias", std::nullopt, {0.0, 1.0}, "required bias"};
const ConfigKey<int> kWindow{"window", 10, 2, 50, "keyframes in the window"};
const ConfigKey<long long> kSeed{"seed", 7, 0, 1000000, "random seed"};
const ConfigKey<bool> kEnabled{"sensor.camera.enabled", false, "camera on"};
const ConfigKey<std::string> kModel{"sensor.camera.model", std::string("pinhole"), {"pinhole", "fisheye"}, "camera model"};
const ConfigKey<std::string> kName{"name", std::string(""), {}, "free text"};
const ConfigKey<std::vector<double>> kNoise{"sensor.imu.noise", std::vector<double>{0.1, 0.2, 0.3}, 3, {0.0, 1.0}, "noise"};
const ConfigKey<std::vector<std::string>> kIgnored{"ignored", {"sky"}, "classes ignored"};
const ConfigMapKey kTable{"table", "probability in [0, 1] per class", "per-class table"};

ConfigSchema schema() {
  ConfigSchema s;
  s.add(kRate).add(kBias).add(kWindow).add(kSeed).add(kEnabled).add(kModel).add(kName).add(kNoise).add(kIgnored).add(kTable);
  return s;
}

}  // namespace

TEST(ConfigSchema, GetReturnsDefaultsWhenAbsentAndValuesWhenGiven) {
  const Config empty;
  EXPECT_DOUBLE_EQ(get(empty, kRate), 200.0);
  EXPECT_EQ(get(empty, kWindow), 10);
  EXPECT_EQ(get(empty, kSeed), 7);
  EXPECT_FALSE(get(empty, kEnabled));
  EXPECT_EQ(get(empty, kModel), "pinhole");
  EXPECT_EQ(get(empty, kNoise), (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_EQ(get(empty, kIgnored), (std::vector<std::string>{"sky"}));

  const Config c = Config::parse(
      "sensor: {imu: {rate: 400, noise: [0.5, 0.5, 0.5]}, camera: {model: fisheye, enabled: true}}\nwindow: 3\nseed: 9\n"
      "ignored: [car]\n",
      "walk.yaml");
  EXPECT_DOUBLE_EQ(get(c, kRate), 400.0);
  EXPECT_EQ(get(c, kWindow), 3);
  EXPECT_EQ(get(c, kSeed), 9);
  EXPECT_TRUE(get(c, kEnabled));
  EXPECT_EQ(get(c, kModel), "fisheye");
  EXPECT_EQ(get(c, kNoise), (std::vector<double>{0.5, 0.5, 0.5}));
  EXPECT_EQ(get(c, kIgnored), (std::vector<std::string>{"car"}));
}

TEST(ConfigSchema, ErrorsNameFileKeyAndRangeAsTheGettersDo) {
  const Config c = Config::parse("sensor: {imu: {rate: 2000, noise: [1, 2]}, camera: {model: orthographic}}\nwindow: x\n",
                                 "walk.yaml", {"seed=-1"});
  const auto rate = schema_config_error([&] { get(c, kRate); });
  EXPECT_EQ(rate, schema_config_error([&] { c.get_double("sensor.imu.rate", 200.0, {1.0, 1000.0}); }));
  EXPECT_NE(rate.find("walk.yaml"), std::string::npos) << rate;
  EXPECT_NE(rate.find("sensor.imu.rate"), std::string::npos) << rate;
  EXPECT_NE(rate.find("value 2000 is outside the allowed range [1, 1000]"), std::string::npos) << rate;

  const auto missing = schema_config_error([&] { get(c, kBias); });
  EXPECT_NE(missing.find("missing; expected a number in [0, 1]"), std::string::npos) << missing;
  EXPECT_NE(schema_config_error([&] { get(c, kWindow); }).find("'x' is not an integer"), std::string::npos);
  const auto seed = schema_config_error([&] { get(c, kSeed); });
  EXPECT_NE(seed.find("--set seed=-1"), std::string::npos) << seed;
  EXPECT_NE(seed.find("[0, 1000000]"), std::string::npos) << seed;
  EXPECT_NE(schema_config_error([&] { get(c, kModel); }).find("'orthographic' is not allowed; expected one of: pinhole, fisheye"),
            std::string::npos);
  EXPECT_NE(schema_config_error([&] { get(c, kNoise); }).find("expected 3 numbers in [0, 1], found 2 values"), std::string::npos);
}

TEST(ConfigSchema, UnknownKeysAreFoundFromTheSchemaNotFromReads) {
  const Config c = Config::parse("sensor: {imu: {rate: 400, rta: 3}}\ntable: {car: 0.5, person: 1}\n", "walk.yaml");
  // Nothing was read, yet the declared keys and the map's free children are known...
  const ConfigSchema s = schema();
  const auto msg = schema_config_error([&] { c.reject_unknown_keys(s); });
  // ...and the misspelt one is reported with the same text as before.
  EXPECT_NE(msg.find("walk.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sensor.imu.rta"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown key (misspelt, or not used by this command)"), std::string::npos) << msg;
  EXPECT_NO_THROW(Config::parse("sensor: {imu: {rate: 400, noise: [0, 0, 0]}}\ntable: {car: 0.5}\n").reject_unknown_keys(s));
  // A map key's own name with a scalar, and prefixes of a declared name, are not declared keys.
  EXPECT_TRUE(s.declares("table.anything"));
  EXPECT_TRUE(s.declares("table"));
  EXPECT_FALSE(s.declares("tab"));
  EXPECT_FALSE(s.declares("sensor.imu"));
  EXPECT_FALSE(s.declares("sensor.imu.rate.x"));
}

TEST(ConfigSchema, DeclaringAKeyTwiceMustAgree) {
  ConfigSchema s = schema();
  EXPECT_NO_THROW(s.add(kRate));
  EXPECT_EQ(s.keys().size(), schema().keys().size());
  const ConfigKey<double> other{"sensor.imu.rate", 100.0, {1.0, 1000.0}, "IMU rate in Hz"};
  EXPECT_THROW(s.add(other), std::logic_error);
}

TEST(ConfigSchema, ListingShowsTypeDefaultRangeAndDoc) {
  const ConfigSchema s = schema();
  const std::string text = format_schema(s, "sensor.imu", false);
  EXPECT_EQ(text,
            "sensor.imu.bias  (number, default (none), [0, 1])\n    required bias\n"
            "sensor.imu.noise  (numbers, default [0.1, 0.2, 0.3], 3 numbers in [0, 1])\n    noise\n"
            "sensor.imu.rate  (number, default 200, [1, 1000])\n    IMU rate in Hz\n");
  EXPECT_EQ(s.listing("sensor").size(), 5u);
  EXPECT_EQ(s.listing("sens").size(), 0u);
  EXPECT_EQ(s.listing().size(), s.keys().size());
  EXPECT_EQ(s.find("name")->default_text(), "\"\"");
  EXPECT_EQ(s.find("ignored")->default_text(), "[sky]");
  EXPECT_EQ(s.find("sensor.camera.model")->allowed, "one of: pinhole, fisheye");
  const std::string md = format_schema(s, "", true);
  EXPECT_NE(md.find("## sensor"), std::string::npos) << md;
  EXPECT_NE(md.find("| `table.*` | map |  | probability in [0, 1] per class | per-class table |"), std::string::npos) << md;
}

TEST(ConfigSchema, DumpWritesGivenKeysAndTheSchemasDefaults) {
  const Config c = Config::parse("sensor: {imu: {rate: 400}}\n", "walk.yaml");
  const Config dumped = Config::parse(c.dump(schema()), "dump.yaml");
  EXPECT_DOUBLE_EQ(dumped.get_double("sensor.imu.rate", {0, 1e4}), 400.0);
  EXPECT_EQ(dumped.get_int("window", 0, 100), 10);
  EXPECT_EQ(dumped.get_string("sensor.camera.model"), "pinhole");
  EXPECT_EQ(dumped.get_string("name"), "");
  EXPECT_EQ(dumped.get_doubles("sensor.imu.noise", 3, {0, 1}), (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_EQ(dumped.get_strings("ignored", {}), (std::vector<std::string>{"sky"}));
  EXPECT_FALSE(dumped.has("sensor.imu.bias"));  // no default to write
  EXPECT_NO_THROW(dumped.reject_unknown_keys(schema()));
}

TEST(ConfigSchema, ReadsAreNotedPerThreadAndPerConfigAndChangeNothing) {
  const Config shared = Config::parse("sensor: {imu: {rate: 400}}\n", "walk.yaml");
  const std::string before = shared.dump();
  ConfigSchema first, second;
  std::thread a([&] {
    const navaid::ConfigReads reads(shared);
    get(shared, kWindow);
    get(shared, kRate);  // given: no default handed out
    first = reads.defaults();
  });
  std::thread b([&] {
    const navaid::ConfigReads reads(shared);
    get(shared, kModel);
    get(Config(), kSeed);  // another Config: not this one's
    second = reads.defaults();
  });
  a.join();
  b.join();
  ASSERT_EQ(first.keys().size(), 1u);
  EXPECT_EQ(first.keys().front().name, "window");
  ASSERT_EQ(second.keys().size(), 1u);
  EXPECT_EQ(second.keys().front().name, "sensor.camera.model");
  EXPECT_EQ(shared.dump(), before);  // reading changed nothing
  const Config dumped = Config::parse(shared.dump(first), "dump.yaml");
  EXPECT_EQ(dumped.get_int("window", 0, 100), 10);
  EXPECT_DOUBLE_EQ(dumped.get_double("sensor.imu.rate", {0, 1000}), 400.0);
  EXPECT_FALSE(dumped.has("sensor.camera.model"));
  EXPECT_THROW(shared.reject_unknown_keys(), std::logic_error);  // the schema says which keys are known
}

// Many threads read (and copy) one loaded Config at once. Before the getters took a lock, the
// read-key set and yaml-cpp's lazily tidied maps were written from every reader (a data race
// ThreadSanitizer reports, and a crash in a trial study: commit bcd29eb).
TEST(ConfigSchema, OneConfigReadFromManyThreads) {
  const Config c = Config::parse(
      "sensor: {imu: {rate: 400, noise: [0.5, 0.5, 0.5]}, camera: {model: fisheye, enabled: true}}\nwindow: 3\n"
      "table: {car: 0.5, person: 1, bus: 0.25}\n",
      "walk.yaml");
  std::atomic<int> wrong{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 300; ++i) {
        if (get(c, kRate) != 400.0 || get(c, kWindow) != 3 || !get(c, kEnabled) || get(c, kModel) != "fisheye" ||
            get(c, kNoise).size() != 3 || c.child_keys("table").size() != 3 || get(c, kSeed) != 7)
          ++wrong;
        if ((i + t) % 50 == 0) {
          const Config copy = c;  // what a trial study does per trial
          if (get(copy, kRate) != 400.0) ++wrong;
        }
        if (i % 100 == 0) c.leaf_keys();
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(wrong.load(), 0);
}
