// Small text idioms of report.html's sections: numbers to a few significant digits (independent of
// the locale) and JSON values as table cells.
#pragma once

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "report/page/report_page.h"

namespace xsect {

/// `v` to `digits` significant digits ("0.0229", "57356", "1.5e-05"); "–" for NaN.
inline std::string shortNumber(double v, int digits = 3) {
  if (std::isnan(v)) return "–";
  if (v == std::floor(v) && std::abs(v) < 1e15) return std::to_string(static_cast<long long>(v));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);  // "C" numeric formatting: xsect never sets a locale
  return buf;
}

/// A JSON value as the text of a table cell (escaped): numbers shortened, arrays joined by spaces,
/// null as "–".
inline std::string cellText(const nlohmann::ordered_json& v) {
  if (v.is_null()) return "–";
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number()) return shortNumber(v.get<double>());
  if (v.is_string()) return htmlEscape(v.get<std::string>());
  if (v.is_array()) {
    std::string s;
    for (const auto& e : v) s += (s.empty() ? "" : " ") + cellText(e);
    return s;
  }
  return htmlEscape(v.dump());
}

/// j[key1][key2]... (a reference into j), or a null value when any is missing.
inline const nlohmann::ordered_json& field(const nlohmann::ordered_json& j, std::initializer_list<const char*> path) {
  static const nlohmann::ordered_json kNull;  // immutable: what a missing field reads as
  const nlohmann::ordered_json* p = &j;
  for (const char* k : path) {
    if (!p->is_object()) return kNull;
    const auto it = p->find(k);
    if (it == p->end()) return kNull;
    p = &*it;
  }
  return *p;
}

}  // namespace xsect
