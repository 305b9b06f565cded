#include "navaid/interaction/guidance_timeline_csv.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <fstream>
#include <optional>

#include "navaid/core/csv_field.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::interaction {

using planning::GuidanceAction;
using planning::GuidanceCommand;

namespace {

constexpr std::array<std::string_view, 11> kColumns = {"t_s",         "type",         "action", "reason",
                                                       "confidence",  "heading_deg",  "steering_deg",
                                                       "rumble",      "hand",         "event",  "value"};

std::string quote(const std::string& s) {
  if (s.find_first_of(",\"") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number(double v) { return fmt::format("{:.9g}", v); }

}  // namespace

Timestamp entry_time(const GuidanceTimelineEntry& entry) {
  return std::visit([](const auto& e) { return e.t; }, entry);
}

std::vector<GuidanceTimelineEntry> parse_guidance_timeline_csv(std::istream& in, const std::string& name) {
  std::vector<GuidanceTimelineEntry> entries;
  std::string line;
  std::size_t line_no = 0;
  bool header = false;
  std::optional<Timestamp> previous;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::optional<std::vector<std::string>> f = split_csv_fields(line);
    if (!f) throw IoError(name, line_no, "unterminated quoted field");
    if (!header) {
      if (f->size() != kColumns.size() || !std::equal(kColumns.begin(), kColumns.end(), f->begin())) {
        throw IoError(name, line_no, fmt::format("not a guidance timeline header; expected {}", fmt::join(kColumns, ",")));
      }
      header = true;
      continue;
    }
    if (f->size() != kColumns.size()) {
      throw IoError(name, line_no, fmt::format("{} fields, expected {}", f->size(), kColumns.size()));
    }
    const auto fail = [&](std::size_t column, const std::string& why) {
      throw IoError(name, line_no, fmt::format("column {}: {} ('{}')", kColumns[column], why, (*f)[column]));
    };
    const auto real = [&](std::size_t column) -> std::optional<double> {
      const std::string& s = (*f)[column];
      if (s.empty()) return std::nullopt;
      std::size_t used = 0;
      double v = 0.0;
      try {
        v = std::stod(s, &used);
      } catch (const std::exception&) {
        fail(column, "not a number");
      }
      if (used != s.size() || !std::isfinite(v)) fail(column, "not a finite number");
      return v;
    };
    const std::optional<Timestamp> t = parse_seconds((*f)[0]);
    if (!t) fail(0, "not a time in seconds");
    if (previous && *t < *previous) fail(0, "time goes backwards");
    previous = t;
    const std::string& type = (*f)[1];
    if (type == "guidance") {
      GuidanceCommand c;
      c.t = *t;
      const auto action = planning::guidance_action_from_string((*f)[2]);
      if (!action) fail(2, "unknown action (go, stop, wait, arrived)");
      const auto reason = planning::guidance_reason_from_string((*f)[3]);
      if (!reason) fail(3, "unknown reason");
      c.action = *action;
      c.reason = *reason;
      const std::optional<double> confidence = real(4);
      if (!confidence || *confidence < 0.0 || *confidence > 1.0) fail(4, "confidence must be in [0, 1]");
      c.confidence = *confidence;
      if (const auto h = real(5)) c.heading_rad = planning::wrap_angle(planning::deg_to_rad(*h));
      if (const auto s = real(6)) c.steering_rad = planning::deg_to_rad(*s);
      if (!(*f)[7].empty()) {
        c.rumble = planning::rumble_state_from_string((*f)[7]);
        if (!c.rumble) fail(7, "unknown rumble state (off, left, right, both)");
      }
      if (!(*f)[8].empty()) {
        c.hand = planning::hand_direction_from_string((*f)[8]);
        if (!c.hand) fail(8, "unknown hand direction");
      }
      if (c.action == GuidanceAction::kGo && !c.heading_rad && !c.rumble && !c.hand) {
        fail(5, "a go command needs heading_deg, rumble or hand");
      }
      entries.emplace_back(c);
    } else if (type == "event") {
      const std::optional<SystemEventKind> kind = system_event_kind_from_string((*f)[9]);
      if (!kind) fail(9, "unknown event");
      entries.emplace_back(SystemEvent{*t, *kind, (*f)[10]});
    } else {
      fail(1, "type must be guidance or event");
    }
  }
  if (!header) throw IoError(name, line_no, "empty file: expected the guidance timeline header");
  return entries;
}

std::vector<GuidanceTimelineEntry> read_guidance_timeline_csv(const std::filesystem::path& file) {
  if (std::filesystem::is_directory(file)) throw IoError(file.string(), "is a folder, expected a guidance timeline CSV");
  std::ifstream in(file);
  if (!in) throw IoError(file.string(), "cannot open");
  return parse_guidance_timeline_csv(in, file.string());
}

void write_guidance_timeline_csv(const std::filesystem::path& file, const std::vector<GuidanceTimelineEntry>& entries) {
  GuidanceTimelineWriter writer(file);
  for (const GuidanceTimelineEntry& entry : entries) writer.add(entry);
  writer.close();
}

GuidanceTimelineWriter::GuidanceTimelineWriter(const std::filesystem::path& file) : name_(file.string()), out_(file) {
  if (!out_) throw IoError(name_, "cannot write");
  out_ << fmt::format("{}\n", fmt::join(kColumns, ","));
}

void GuidanceTimelineWriter::add(const GuidanceTimelineEntry& entry) {
  if (const auto* c = std::get_if<GuidanceCommand>(&entry)) {
    out_ << fmt::format("{},guidance,{},{},{},{},{},{},{},,\n", format_seconds(c->t), planning::to_string(c->action),
                        planning::to_string(c->reason), number(c->confidence),
                        c->heading_rad ? number(planning::rad_to_deg(*c->heading_rad)) : "",
                        c->steering_rad ? number(planning::rad_to_deg(*c->steering_rad)) : "",
                        c->rumble ? std::string(planning::to_string(*c->rumble)) : "",
                        c->hand ? std::string(planning::to_string(*c->hand)) : "");
  } else {
    const SystemEvent& e = std::get<SystemEvent>(entry);
    out_ << fmt::format("{},event,,,,,,,,{},{}\n", format_seconds(e.t), to_string(e.kind), quote(e.value));
  }
  ++count_;
}

void GuidanceTimelineWriter::close() {
  out_.close();
  if (!out_) throw IoError(name_, "write failed");
}

}  // namespace navaid::interaction
