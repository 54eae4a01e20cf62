// JSON output. Every JSON file plslam writes (stats.json, dense_products.json, eval's and
// bench's results...) is built as a Json value and turned into text by jsonText, so that
// strings are escaped and every number has one format: nlohmann-json's, the shortest text
// that reads back as the same double (NaN and infinities become null).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace plslam {

/// Members keep the order they were added in: the files are read by people too.
using Json = nlohmann::ordered_json;

/// `value` as text with a final newline, indented by `indent` spaces (-1: on one line).
/// Bytes that are not UTF-8 (a path in another encoding) become U+FFFD instead of failing.
std::string jsonText(const Json& value, int indent = 2);

}  // namespace plslam
