#include "navaid/interaction/message_templates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <map>

#include "navaid/core/errors.hpp"

namespace navaid::interaction {
namespace {

constexpr std::size_t kLanguages = 2;  // en, de: the column order of every table below
using Texts = std::array<std::string_view, kLanguages>;

/// How an argument's value goes into the text.
enum class ArgKind {
  kWord,    ///< a word of the system, translated through its word list
  kNumber,  ///< a decimal number, as it is
  kName,    ///< a name (road, place, fault), as it is
};

struct Word {
  std::string_view value;
  Texts text;
};

struct Arg {
  std::string_view name;
  ArgKind kind = ArgKind::kName;
  bool optional = false;
  std::vector<Word> words;  // kWord only
};

struct Template {
  std::string_view id;
  std::vector<Arg> args;
  /// {name} is replaced by the argument; [ ... ] is kept only when every argument inside it is
  /// given (optional parts such as " onto {road}").
  Texts text;
};

const std::vector<Word> kSides{{"left", {"left", "links"}}, {"right", {"right", "rechts"}}};

// Full phrases, because "hold" and "forward" do not fit one "Move {direction}" sentence.
const std::vector<Word> kHandDirections{
    {"hold", {"Hold still", "Hand ruhig halten"}},
    {"right", {"Move right", "Nach rechts"}},
    {"up-right", {"Move up and right", "Nach rechts oben"}},
    {"up", {"Move up", "Nach oben"}},
    {"up-left", {"Move up and left", "Nach links oben"}},
    {"left", {"Move left", "Nach links"}},
    {"down-left", {"Move down and left", "Nach links unten"}},
    {"down", {"Move down", "Nach unten"}},
    {"down-right", {"Move down and right", "Nach rechts unten"}},
    {"forward", {"Reach forward", "Nach vorne greifen"}},
    {"backward", {"Pull back", "Zurückziehen"}},
};

// BYU: the rumble side is the freer side, both means stop and search (Table 2.1).
const std::vector<Word> kObstacleWays{{"left", {"go left", "links ausweichen"}},
                                      {"right", {"go right", "rechts ausweichen"}},
                                      {"stop", {"stop", "anhalten"}}};

const std::vector<Word> kRouteTurns{{"left", {"turn left", "links abbiegen"}},
                                    {"right", {"turn right", "rechts abbiegen"}},
                                    {"straight", {"continue straight", "geradeaus weiter"}}};

// What each estimator mode means to the user (EstimatorMode names, core/state_estimate.hpp).
const std::vector<Word> kModes{{"initializing", {"starting", "Start"}},
                               {"rgbd-vio", {"camera and depth", "Kamera und Tiefe"}},
                               {"vio", {"camera only", "nur Kamera"}},
                               {"imu-only", {"motion sensors only", "nur Bewegungssensoren"}},
                               {"lost", {"lost", "verloren"}}};

const std::vector<Template>& templates() {
  static const std::vector<Template> kTemplates{
      {"stop", {}, {"Stop!", "Halt!"}},
      {"arrived", {}, {"You have arrived.", "Sie sind angekommen."}},
      {"target_reached", {}, {"Target reached.", "Ziel erreicht."}},
      {"arrived_facing",
       {{"clock", ArgKind::kNumber, false, {}}},
       {"You have arrived. The destination is at {clock} o'clock.", "Sie sind angekommen. Das Ziel liegt auf {clock} Uhr."}},
      {"move_hand", {{"direction", ArgKind::kWord, false, kHandDirections}}, {"{direction}.", "{direction}."}},
      {"prepare_turn", {{"side", ArgKind::kWord, false, kSides}}, {"Prepare to turn {side}.", "Gleich {side} abbiegen."}},
      {"bear", {{"side", ArgKind::kWord, false, kSides}}, {"Bear {side}.", "Etwas nach {side}."}},
      {"obstacle", {{"way", ArgKind::kWord, false, kObstacleWays}}, {"Obstacle ahead, {way}.", "Hindernis voraus, {way}."}},
      {"route",
       {{"distance_m", ArgKind::kNumber, false, {}},
        {"turn", ArgKind::kWord, false, kRouteTurns},
        {"road", ArgKind::kName, true, {}}},
       {"In {distance_m} meters, {turn}[ onto {road}].", "In {distance_m} Metern {turn}[, {road}]."}},
      {"route_crossing",
       {{"distance_m", ArgKind::kNumber, false, {}}, {"road", ArgKind::kName, true, {}}},
       {"In {distance_m} meters, a crossing[: {road}].", "In {distance_m} Metern ein Überweg[: {road}]."}},
      {"route_steps", {{"distance_m", ArgKind::kNumber, false, {}}}, {"In {distance_m} meters, steps.", "In {distance_m} Metern Stufen."}},
      {"destination_set", {{"place", ArgKind::kName, false, {}}}, {"Destination set: {place}.", "Ziel gesetzt: {place}."}},
      {"no_instruction", {}, {"No instruction yet.", "Noch keine Anweisung."}},
      {"guidance_stopped", {}, {"Guidance stopped.", "Führung beendet."}},
      {"not_understood", {}, {"Sorry, I did not understand.", "Das habe ich nicht verstanden."}},
      {"locating", {}, {"Locating, please wait.", "Ortung läuft, bitte warten."}},
      {"located", {}, {"Location found.", "Position gefunden."}},
      {"initialized", {}, {"Navigation ready.", "Navigation bereit."}},
      {"mode_changed", {{"mode", ArgKind::kWord, false, kModes}}, {"Tracking mode: {mode}.", "Ortungsmodus: {mode}."}},
      {"network_lost", {}, {"Network lost, object recognition paused.", "Netzwerk verloren, Objekterkennung pausiert."}},
      {"network_restored", {}, {"Network restored.", "Netzwerk wieder verfügbar."}},
      {"link_lost", {}, {"Vibration link lost.", "Verbindung zum Vibrationsgerät verloren."}},
      {"link_restored", {}, {"Vibration link restored.", "Verbindung zum Vibrationsgerät wiederhergestellt."}},
      {"camera_fault", {{"what", ArgKind::kName, false, {}}}, {"Camera fault: {what}.", "Kamerafehler: {what}."}},
  };
  return kTemplates;
}

bool is_number(std::string_view s) {
  if (s.empty()) return false;
  bool digit = false, point = false;
  for (const char c : s) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      digit = true;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      return false;
    }
  }
  return digit;
}

std::string word_list(const std::vector<Word>& words) {
  std::string out;
  for (const Word& w : words) out += (out.empty() ? "" : ", ") + std::string(w.value);
  return out;
}

/// The argument's words in the text.
std::string argument_text(const Template& t, const Arg& arg, const std::string& value, std::size_t lang) {
  switch (arg.kind) {
    case ArgKind::kWord: {
      const auto it = std::find_if(arg.words.begin(), arg.words.end(), [&](const Word& w) { return w.value == value; });
      if (it == arg.words.end()) {
        throw Error(fmt::format("message '{}': {} '{}' is not one of {}", t.id, arg.name, value, word_list(arg.words)));
      }
      return std::string(it->text[lang]);
    }
    case ArgKind::kNumber:
      if (!is_number(value)) throw Error(fmt::format("message '{}': {} '{}' is not a number", t.id, arg.name, value));
      return value;
    case ArgKind::kName:
      if (value.find_first_not_of(" \t") == std::string::npos) {
        throw Error(fmt::format("message '{}': {} is blank", t.id, arg.name));
      }
      return value;
  }
  return value;
}

/// Fills {name} placeholders from `values`; a [ ... ] part is dropped when one of its
/// placeholders has no value.
std::string fill(std::string_view text, const std::map<std::string, std::string, std::less<>>& values) {
  std::string out;
  std::string group;
  bool in_group = false, group_complete = true;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    std::string& target = in_group ? group : out;
    if (c == '[') {
      in_group = true;
      group.clear();
      group_complete = true;
    } else if (c == ']') {
      if (group_complete) out += group;
      in_group = false;
    } else if (c == '{') {
      const std::size_t end = text.find('}', i);
      const auto it = values.find(text.substr(i + 1, end - i - 1));
      if (it == values.end()) {
        group_complete = false;
      } else {
        target += it->second;
      }
      i = end;
    } else {
      target += c;
    }
  }
  return out;
}

std::size_t language_index(std::string_view language) {
  const auto& langs = template_languages();
  const auto it = std::find(langs.begin(), langs.end(), language);
  if (it == langs.end()) {
    throw Error(fmt::format("no message templates for language '{}' (there are: en, de)", language));
  }
  return static_cast<std::size_t>(it - langs.begin());
}

}  // namespace

const std::vector<std::string_view>& template_languages() {
  static const std::vector<std::string_view> kNames{"en", "de"};
  return kNames;
}

bool is_template_language(std::string_view language) {
  const auto& langs = template_languages();
  return std::find(langs.begin(), langs.end(), language) != langs.end();
}

const std::vector<MessageTemplateInfo>& template_ids() {
  static const std::vector<MessageTemplateInfo> kInfo = [] {
    std::vector<MessageTemplateInfo> info;
    for (const Template& t : templates()) {
      MessageTemplateInfo i{t.id, {}};
      for (const Arg& a : t.args) i.args.push_back(std::string(a.name) + (a.optional ? "?" : ""));
      info.push_back(std::move(i));
    }
    return info;
  }();
  return kInfo;
}

std::string render_message(const SpokenMessage& message, std::string_view language) {
  const std::size_t lang = language_index(language);
  const auto& all = templates();
  const auto t = std::find_if(all.begin(), all.end(), [&](const Template& x) { return x.id == message.id; });
  if (t == all.end()) throw Error(fmt::format("no message template '{}'", message.id));
  for (const auto& given : message.args) {
    const std::string& name = given.first;  // a named copy: C++17 lambdas cannot capture bindings
    if (std::none_of(t->args.begin(), t->args.end(), [&](const Arg& a) { return a.name == name; })) {
      throw Error(fmt::format("message '{}' takes no argument '{}'", t->id, name));
    }
  }
  std::map<std::string, std::string, std::less<>> values;
  for (const Arg& arg : t->args) {
    const auto it = message.args.find(std::string(arg.name));
    if (it == message.args.end()) {
      if (!arg.optional) throw Error(fmt::format("message '{}' needs argument '{}'", t->id, arg.name));
      continue;
    }
    values.emplace(std::string(arg.name), argument_text(*t, arg, it->second, lang));
  }
  return fill(t->text[lang], values);
}

}  // namespace navaid::interaction
