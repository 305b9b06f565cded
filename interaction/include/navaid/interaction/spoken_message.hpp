#pragma once
// A message to speak, before it is words: a category (eLabrador's route / action / system
// information), a template id and its arguments. Templates (message_templates.hpp) turn it into
// text in the configured language; the scheduler knows its duration once it is synthesized.
#include <map>
#include <string>
#include <string_view>

namespace navaid::interaction {

enum class MessageCategory { kRoute, kAction, kSystem };
std::string_view to_string(MessageCategory category);

struct SpokenMessage {
  MessageCategory category = MessageCategory::kSystem;
  /// Template id, e.g. "stop", "prepare_turn", "arrived", "locating", "mode_changed" (the list and
  /// each template's arguments: message_templates.hpp).
  std::string id;
  /// Named arguments, e.g. {"side", "left"}, {"distance_m", "49"}, {"mode", "VIO"}.
  std::map<std::string, std::string> args;

  bool operator==(const SpokenMessage& other) const {
    return category == other.category && id == other.id && args == other.args;
  }
};

}  // namespace navaid::interaction
