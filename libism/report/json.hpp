#pragma once
// The JSON value of reports: nlohmann-json's ordered_json, whose objects keep
// their insertion order so that reports read in the order the work was done.
// Non-finite numbers are written as null (JSON has no infinity).
#include <nlohmann/json.hpp>

#include <string>

namespace ism {

using Json = nlohmann::ordered_json;

/// A report as text: two-space indentation, `"key": value`, invalid UTF-8 in
/// strings (e.g. a file name) replaced by U+FFFD instead of throwing.
inline std::string report_text(const Json& report) {
  return report.dump(2, ' ', false, Json::error_handler_t::replace);
}

}  // namespace ism
