#include "navaid/interaction/spoken_message.hpp"

#include "navaid/core/enum_names.hpp"

namespace navaid::interaction {

namespace {

constexpr NameTable<MessageCategory, 3> kSpokenMessageNames{{
    {MessageCategory::kRoute, "route"},
    {MessageCategory::kAction, "action"},
    {MessageCategory::kSystem, "system"},
}};

}  // namespace

std::string_view to_string(MessageCategory category) { return enum_name(kSpokenMessageNames, category); }

}  // namespace navaid::interaction
