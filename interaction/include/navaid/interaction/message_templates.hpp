#pragma once
// The words for every SpokenMessage, in English and German. eLabrador speaks three kinds of
// information (route, action, system); the texts are short because a message competes with the
// street for the user's attention and the scheduler keeps 2.3 s between two of them.
//
// A template is a text with {name} placeholders; arguments that are words of the system
// ("left", "up-right", "rgbd-vio") are translated before they are put in, numbers and names
// (distances, roads, places) go in as they are. Every id the cue generator uses is here; the
// full list with each template's arguments is template_ids() and docs/interaction.md.
#include <string>
#include <string_view>
#include <vector>

#include "navaid/interaction/spoken_message.hpp"

namespace navaid::interaction {

/// The template languages: {"en", "de"}.
const std::vector<std::string_view>& template_languages();
bool is_template_language(std::string_view language);

struct MessageTemplateInfo {
  std::string_view id;
  /// Required arguments, then optional ones marked with a trailing '?'.
  std::vector<std::string> args;
};
/// Every template id with its arguments, in a fixed order.
const std::vector<MessageTemplateInfo>& template_ids();

/// The text of `message` in `language`. Throws navaid::Error naming the id for an unknown
/// template, a missing required argument, an argument the template does not take, or an
/// argument value outside its word list (a side other than left/right, ...), and naming the
/// language when it has no templates.
std::string render_message(const SpokenMessage& message, std::string_view language);

}  // namespace navaid::interaction
