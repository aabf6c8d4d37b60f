#pragma once
/// \file parameters.hpp
/// Every tunable setting of a matcher — its segmenter's (`VoronoiSegmenter::Params`), its own
/// (`MatcherParams`), its clusterer's and selection's (the shipped ones') — by a dotted name, e.g.
/// `rooms.door_width_m`, `decision.min_agreement`, `selection.verify_candidates`: one table
/// (parameter_table.hpp) that the program's `--set NAME=VALUE` and `areamatch parameters`,
/// Python's `params={...}` and `areamatch.parameters()`, and the reference in docs/parameters.md
/// all read, so that none of them lists the settings again.
///
/// \code
/// areamatch::Matcher<> matcher;
/// areamatch::set_parameters(matcher, {{"rooms.door_width_m", "1.5"}, {"decision.min_agreement", "0.9"},
///                                     {"selection.verify_candidates", "64"}});
/// \endcode
///
/// Values are text as a person writes them: numbers, `true`/`false`, lists as `2,1.2,0.7`.
/// Lengths are in metres, areas in m², angles in radians (the suffix of the name says so).
/// The two fields the segmenter sets itself from others (`skeleton.keep_clearance_m`,
/// `areas.min_clearance_m`) are not settable and not listed.

#include "detail/format.hpp"
#include "detail/nearest_name.hpp"
#include "error.hpp"
#include "parameter_table.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

/// A name and the text of its value, as `set_parameters` takes them.
struct ParameterSetting {
  std::string name;
  std::string value;
};

/// One row of the table with its value: what `areamatch parameters` prints.
struct ParameterRow {
  std::string name;
  std::string value;    ///< the value as text (`set_parameters` reads it back exactly)
  std::string meaning;  ///< one line
  std::string of;                ///< whose: "segmenter", "matcher", "clusterer" or "selection"
  bool shapes_map_data = false;  ///< see `ParameterInfo::shapes_map_data`
};

namespace detail {

inline std::string parameter_text(double v) { return format_double(v); }
inline std::string parameter_text(bool v) { return v ? "true" : "false"; }
template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
std::string parameter_text(T v) {
  return std::to_string(v);
}
template <class List>
auto parameter_text(const List& values) -> decltype(values.begin(), std::string()) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ",") + format_double(v);
  return out;
}

inline double parse_parameter_number(const std::string& name, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
    throw parameter_error("parameter " + name + " must be a number, got '" + text + "'");
  }
  return v;
}

inline void parse_parameter(const std::string& name, const std::string& text, double& out) {
  out = parse_parameter_number(name, text);
}
inline void parse_parameter(const std::string& name, const std::string& text, bool& out) {
  if (text == "true" || text == "1") out = true;
  else if (text == "false" || text == "0") out = false;
  else throw parameter_error("parameter " + name + " must be true or false, got '" + text + "'");
}
template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
void parse_parameter(const std::string& name, const std::string& text, T& out) {
  const double v = parse_parameter_number(name, text);
  const double low = std::is_signed_v<T> ? static_cast<double>(std::numeric_limits<T>::min()) : 0.0;
  if (v != std::floor(v) || v < low || v > 2147483647.0) {
    throw parameter_error("parameter " + name + " must be a whole number" + (std::is_signed_v<T> ? "" : " >= 0") +
                          " (at most 2147483647), got '" + text + "'");
  }
  out = static_cast<T>(v);
}
inline std::vector<double> parse_parameter_list(const std::string& name, const std::string& text) {
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    values.push_back(parse_parameter_number(name, text.substr(start, comma == std::string::npos ? comma : comma - start)));
    if (comma == std::string::npos) return values;
    start = comma + 1;
  }
}
inline void parse_parameter(const std::string& name, const std::string& text, std::vector<double>& out) {
  out = parse_parameter_list(name, text);
}
template <std::size_t N>
void parse_parameter(const std::string& name, const std::string& text, std::array<double, N>& out) {
  const std::vector<double> values = parse_parameter_list(name, text);
  if (values.size() != N) {
    throw parameter_error("parameter " + name + " takes " + std::to_string(N) + " numbers, got " +
                          std::to_string(values.size()));
  }
  std::copy(values.begin(), values.end(), out.begin());
}

/// Which part of a matcher a setting belongs to, by its name.
inline std::string parameter_owner(const std::string& name) {
  for (const char* part : {"clusterer", "selection"}) {
    if (name.rfind(std::string(part) + ".", 0) == 0) return part;
  }
  bool segmenter = false;
  const VoronoiSegmenterParams defaults;
  for_each_segmenter_parameter(defaults, [&](const ParameterInfo& info, const auto&) { segmenter = segmenter || info.name == name; });
  return segmenter ? "segmenter" : "matcher";
}

}  // namespace detail

/// Every setting of `matcher` (any `Matcher<...>`: `for_each_parameter`) with its value, in the
/// table's order.
template <class M>
std::vector<ParameterRow> parameter_rows(const M& matcher) {
  std::vector<ParameterRow> rows;
  for_each_parameter(matcher, [&rows](const ParameterInfo& info, const auto& field) {
    rows.push_back({info.name, detail::parameter_text(field), info.meaning, detail::parameter_owner(info.name), info.shapes_map_data});
  });
  return rows;
}

/// The table as Markdown (docs/parameters.md holds `Matcher<>`'s): setting, default, what it
/// does; a `*` marks the settings that shape a prepared map.
template <class M>
std::string parameters_markdown(const M& matcher) {
  std::string out = "| setting | default | what it does |\n|---|---|---|\n";
  for (const ParameterRow& r : parameter_rows(matcher)) {
    out += "| `" + r.name + "`" + (r.shapes_map_data ? " *" : "") + " | " + r.value + " | " + r.meaning + " |\n";
  }
  return out;
}

/// Whether `name` is a setting of `VoronoiSegmenter`.
inline bool parameter_is_segmenters(const std::string& name) { return detail::parameter_owner(name) == "segmenter"; }

/// Sets each named setting of `matcher` (any `Matcher<...>`), in order, from its text; then
/// validates the parameters it touched. Throws `parameter_error` naming the setting for a name
/// this matcher does not have (with the nearest one it has; a segmenter setting where the
/// segmenter is not `VoronoiSegmenter`), a value that does not read as the field's type, or a
/// value `validate()` refuses; `matcher` is then left as it was.
template <class M>
void set_parameters(M& matcher, const std::vector<ParameterSetting>& settings) {
  M changed = matcher;
  for (const ParameterSetting& s : settings) {
    bool found = false;
    for_each_parameter(changed, [&](const ParameterInfo& info, auto& field) {
      if (found || info.name != s.name) return;
      detail::parse_parameter(s.name, s.value, field);
      found = true;
    });
    if (found) continue;
    if (parameter_is_segmenters(s.name)) {
      throw parameter_error("setting " + s.name + ": only VoronoiSegmenter has it; set the parameters of your own segmenter instead");
    }
    std::vector<std::string> names;
    for (const ParameterRow& row : parameter_rows(changed)) names.push_back(row.name);
    const std::string near = detail::nearest_name(s.name, names);
    throw parameter_error("no parameter named '" + s.name + "'" + (near.empty() ? "" : " (did you mean " + near + "?)") +
                          "; `areamatch parameters` lists them");
  }
  if constexpr (detail::policy_has_params<decltype(M::segmenter), VoronoiSegmenterParams>()) changed.segmenter.params.validate();
  changed.params.validate();
  if constexpr (detail::policy_has_params<decltype(M::selection), WholeMapSelection::Params>()) changed.selection.params.validate();
  matcher = std::move(changed);
}

/// The first setting that shapes a prepared map's data (`ParameterInfo::shapes_map_data`) and
/// differs between `a` and `b`; "" when none does, i.e. a map prepared with `a` serves a matcher
/// with `b`.
inline std::string map_data_setting_differing(const MatcherParams& a, const MatcherParams& b) {
  std::vector<std::string> texts;
  for_each_matcher_parameter(a, [&](const ParameterInfo& info, const auto& field) {
    if (info.shapes_map_data) texts.push_back(detail::parameter_text(field));
  });
  std::size_t i = 0;
  std::string differing;
  for_each_matcher_parameter(b, [&](const ParameterInfo& info, const auto& field) {
    if (!info.shapes_map_data) return;
    if (differing.empty() && texts[i] != detail::parameter_text(field)) differing = info.name;
    ++i;
  });
  return differing;
}

}  // namespace areamatch
