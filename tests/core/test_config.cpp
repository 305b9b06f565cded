#include <gtest/gtest.h>

#include "navaid/core/config.hpp"
#include "navaid/core/config_reads.hpp"
#include "navaid/core/config_schema.hpp"
#include "navaid/core/errors.hpp"
#include "test_support.hpp"

using navaid::Config;
using navaid::ConfigError;
using navaid::Range;

namespace {

const char* kYaml = R"(
sensor:
  imu:
    rate: 200
    noise: [0.1, 0.2, 0.3]
  camera:
    model: pinhole
    enabled: true
window: 10
)";

// Runs `f`, expects a ConfigError and returns its message.
template <typename F>
std::string config_error(F&& f) {
  return navaid::testing::error_message<ConfigError>(std::forward<F>(f));
}

}  // namespace

TEST(Config, ReadsTypedValues) {
  const Config c = Config::parse(kYaml, "walk.yaml");
  EXPECT_DOUBLE_EQ(c.get_double("sensor.imu.rate", {1, 1000}), 200.0);
  EXPECT_EQ(c.get_int("window", 2, 50), 10);
  EXPECT_TRUE(c.get_bool("sensor.camera.enabled"));
  EXPECT_EQ(c.get_string("sensor.camera.model", {"pinhole", "fisheye"}), "pinhole");
  EXPECT_EQ(c.get_doubles("sensor.imu.noise", 3, {0, 1}), (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_DOUBLE_EQ(c.get_double("sensor.gps.rate", 5.0, {1, 10}), 5.0);
  EXPECT_EQ(c.child_keys("sensor"), (std::vector<std::string>{"imu", "camera"}));
}

TEST(Config, OutOfRangeNamesFileKeyAndRange) {
  const Config c = Config::parse(kYaml, "walk.yaml");
  const auto msg = config_error([&] { c.get_double("sensor.imu.rate", {1, 100}); });
  EXPECT_NE(msg.find("walk.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sensor.imu.rate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[1, 100]"), std::string::npos) << msg;
}

TEST(Config, MissingKeyWrongTypeAndDisallowedString) {
  const Config c = Config::parse(kYaml, "walk.yaml");
  EXPECT_NE(config_error([&] { c.get_double("sensor.imu.bias", {0, 1}); }).find("missing"), std::string::npos);
  EXPECT_NE(config_error([&] { c.get_int("sensor.camera.model", 0, 5); }).find("not an integer"), std::string::npos);
  EXPECT_NE(config_error([&] { c.get_string("sensor.camera.model", {"fisheye"}); }).find("one of: fisheye"),
            std::string::npos);
  EXPECT_NE(config_error([&] { c.get_doubles("sensor.imu.noise", 4, {0, 1}); }).find("found 3 values"),
            std::string::npos);
  EXPECT_NE(config_error([&] { c.get_double("sensor.imu", {0, 1}); }).find("found a map"), std::string::npos);
  EXPECT_NE(config_error([&] { c.get_bool("window"); }).find("true or false"), std::string::npos);
}

TEST(Config, NonFiniteNumbersRejected) {
  const Config c = Config::parse("a: .nan\nb: .inf\n", "x.yaml");
  EXPECT_NE(config_error([&] { c.get_double("a", {-1e9, 1e9}); }).find("not a finite number"), std::string::npos);
  EXPECT_NE(config_error([&] { c.get_double("b", {-1e9, 1e9}); }).find("not a finite number"), std::string::npos);
}

TEST(Config, OverridesReplaceAndCreateKeysAndAreNamedInErrors) {
  const Config c = Config::parse(kYaml, "walk.yaml",
                                 {"sensor.imu.rate=400", "sensor.gps.rate=5", "sensor.imu.noise=[1,2,3]"});
  EXPECT_DOUBLE_EQ(c.get_double("sensor.imu.rate", {1, 1000}), 400.0);
  EXPECT_DOUBLE_EQ(c.get_double("sensor.gps.rate", {1, 10}), 5.0);
  const auto msg = config_error([&] { c.get_doubles("sensor.imu.noise", 3, {0, 1}); });
  EXPECT_NE(msg.find("--set sensor.imu.noise=[1,2,3]"), std::string::npos) << msg;
  EXPECT_EQ(c.origin("sensor.camera.model"), "walk.yaml");
}

TEST(Config, MalformedOverrides) {
  Config c = Config::parse(kYaml, "walk.yaml");
  EXPECT_NE(config_error([&] { c.apply_override("sensor.imu.rate"); }).find("key.sub.key=value"), std::string::npos);
  EXPECT_NE(config_error([&] { c.apply_override("=3"); }).find("key.sub.key=value"), std::string::npos);
  EXPECT_NE(config_error([&] { c.apply_override("sensor..rate=3"); }).find("empty path"), std::string::npos);
  EXPECT_NE(config_error([&] { c.apply_override("window.size=3"); }).find("holds a value"), std::string::npos);
}

TEST(Config, UnknownKeysAreRejectedByTheDeclaredKeys) {
  const Config c = Config::parse(kYaml, "walk.yaml", {"sensor.imu.rtae=3"});
  navaid::ConfigSchema schema;
  schema.add(navaid::ConfigKey<double>{"sensor.imu.rate", std::nullopt, {1, 1000}, "rate"})
      .add(navaid::ConfigKey<std::vector<double>>{"sensor.imu.noise", std::nullopt, 3, {0, 1}, "noise"})
      .add(navaid::ConfigKey<std::string>{"sensor.camera.model", std::nullopt, {}, "model"})
      .add(navaid::ConfigKey<bool>{"sensor.camera.enabled", std::nullopt, "enabled"})
      .add(navaid::ConfigKey<int>{"window", std::nullopt, 1, 20, "window"});
  const auto msg = config_error([&] { c.reject_unknown_keys(schema); });
  EXPECT_NE(msg.find("sensor.imu.rtae"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--set"), std::string::npos) << msg;
}

TEST(Config, FileErrors) {
  EXPECT_NE(config_error([] { Config::load("/nonexistent/navaid.yaml"); }).find("cannot open"), std::string::npos);
  navaid::testing::ScratchDir dir("config");
  navaid::testing::write_text(dir / "bad.yaml", "a: [1, 2\nb: 3\n");
  const auto msg = config_error([&] { Config::load(dir / "bad.yaml"); });
  EXPECT_NE(msg.find("bad.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not valid YAML"), std::string::npos) << msg;
  navaid::testing::write_text(dir / "list.yaml", "- 1\n- 2\n");
  EXPECT_NE(config_error([&] { Config::load(dir / "list.yaml"); }).find("map of keys"), std::string::npos);
}

// Found by fuzz_config: a list or map used as a key escaped as a yaml-cpp conversion error.
TEST(Config, AKeyThatIsAListOrMapIsAClearError) {
  auto msg = config_error([] { Config::parse("{}:\n    max_iterations: 12\n", "odd.yaml"); });
  EXPECT_NE(msg.find("odd.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("a key must be a name"), std::string::npos) << msg;
  msg = config_error([] { Config::parse("estimator:\n  [a, b]: 1\n", "odd.yaml"); });
  EXPECT_NE(msg.find("'estimator'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 2"), std::string::npos) << msg;
  Config c = Config::parse(kYaml, "walk.yaml");
  EXPECT_NE(config_error([&] { c.apply_override("estimator={[x]: 1}"); }).find("a key must be a name"),
            std::string::npos);
}

TEST(Config, DumpRoundTripsThroughParse) {
  const Config c = Config::parse(kYaml, "walk.yaml", {"sensor.imu.rate=400"});
  const Config d = Config::parse(c.dump(), "dump.yaml");
  EXPECT_DOUBLE_EQ(d.get_double("sensor.imu.rate", {1, 1000}), 400.0);
  EXPECT_EQ(d.dump(), c.dump());
}

TEST(Config, ReadingNeverChangesTheGivenKeys) {
  const Config c = Config::parse(kYaml, "walk.yaml");
  EXPECT_FALSE(c.has("sensor.gps.rate"));
  EXPECT_DOUBLE_EQ(c.get_double("sensor.gps.rate", 5.0, {1, 10}), 5.0);
  EXPECT_FALSE(c.has("sensor.gps.rate"));
  EXPECT_FALSE(c.has("sensor.imu.rate.deeper"));
  EXPECT_DOUBLE_EQ(c.get_double("sensor.imu.rate", 7.0, {1, 1000}), 200.0);
}

TEST(Config, DumpHoldsTheDefaultsThatWereReadSoARunFolderHasTheWholeConfiguration) {
  using navaid::ConfigKey;
  const Config c = Config::parse(kYaml, "walk.yaml");
  const Config other = c;  // reads of another Config are not this one's
  const navaid::ConfigReads reads(c);
  EXPECT_DOUBLE_EQ(get(c, ConfigKey<double>{"sensor.gps.rate", 0.3, {0, 10}, ""}), 0.3);
  EXPECT_EQ(get(c, ConfigKey<int>{"sensor.gps.satellites", 12, 0, 40, ""}), 12);
  EXPECT_FALSE(get(c, ConfigKey<bool>{"estimator.gps.enabled", false, ""}));
  EXPECT_EQ(get(c, ConfigKey<std::string>{"estimator.mode", std::string("rgbd-vio"), {}, ""}), "rgbd-vio");
  EXPECT_EQ(get(c, ConfigKey<std::vector<std::string>>{"layers", {"map", "plan"}, ""}),
            (std::vector<std::string>{"map", "plan"}));
  EXPECT_DOUBLE_EQ(get(c, ConfigKey<double>{"sensor.gps.rate", 0.7, {0, 10}, ""}), 0.7);  // a second default is not recorded
  EXPECT_EQ(get(other, ConfigKey<int>{"sensor.gps.week", 3, 0, 9, ""}), 3);
  const std::string dumped = c.dump(reads.defaults());
  EXPECT_EQ(dumped.find("week"), std::string::npos) << dumped;
  EXPECT_EQ(c.dump(), Config::parse(kYaml, "walk.yaml").dump());  // reading changed nothing
  EXPECT_NE(dumped.find("rate: 0.3\n"), std::string::npos) << dumped;  // shortest round-trip text
  const Config d = Config::parse(dumped, "dump.yaml");
  EXPECT_DOUBLE_EQ(d.get_double("sensor.gps.rate", {0, 10}), 0.3);
  EXPECT_EQ(d.get_int("sensor.gps.satellites", 0, 40), 12);
  EXPECT_FALSE(d.get_bool("estimator.gps.enabled"));
  EXPECT_EQ(d.get_string("estimator.mode"), "rgbd-vio");
  EXPECT_EQ(d.get_strings("layers", {}), (std::vector<std::string>{"map", "plan"}));
  EXPECT_DOUBLE_EQ(d.get_double("sensor.imu.rate", {1, 1000}), 200.0);  // the given keys stay as given
  EXPECT_EQ(Config::parse(d.dump(), "again.yaml").dump(), d.dump());
}
