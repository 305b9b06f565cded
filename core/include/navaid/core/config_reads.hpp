#pragma once
// What a command's reads resolved, for its run folder's config.yaml.
//
// A loaded Config never changes: reading it records nothing. A command that writes the whole
// configuration it used (given keys plus the defaults it fell back on) creates a ConfigReads on
// its Config before it reads its options; while it lives, get(config, key) (navaid/core/
// config_schema.hpp) of that Config object on this thread notes each default it hands out for an
// absent key, in the order first read (a key read twice keeps its first default).
// config.dump(reads.defaults()) then writes them beside the given keys. Reads of other Config
// objects (a copy, a recording's simulation.yaml) and of other threads are not noted.
#include "navaid/core/config_schema.hpp"

namespace navaid {

class ConfigReads {
 public:
  /// Starts noting the reads of `config` on this thread (an enclosing ConfigReads resumes when
  /// this one ends). `config` must outlive this object.
  explicit ConfigReads(const Config& config);
  ~ConfigReads();
  ConfigReads(const ConfigReads&) = delete;
  ConfigReads& operator=(const ConfigReads&) = delete;

  /// The defaults handed out so far, as declarations whose default is the value used.
  const ConfigSchema& defaults() const { return defaults_; }

  /// Notes a default handed out for `config` on this thread (no-op unless a ConfigReads on this
  /// thread watches that object).
  static void note(const Config& config, const ConfigKeyInfo& used);

 private:
  const Config* config_;
  ConfigSchema defaults_;
  ConfigReads* outer_;
};

}  // namespace navaid
