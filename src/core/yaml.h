// YAML documents read with yaml-cpp, with messages that name the file and line. The
// readers of configuration files, grid.yaml and camera-to-base files share these so that
// every refusal reads "<file>:<line>: <problem>".
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <vector>

namespace plslam {

/// "<source>:<line>" of a position in a YAML document (lines counted from 1), or `source`
/// alone when yaml-cpp does not know the position.
std::string yamlAt(const std::string& source, const YAML::Mark& mark);

/// A scalar's text as a finite number, or nullopt (not a scalar, not all of it a number,
/// infinite or NaN).
std::optional<double> yamlNumber(const YAML::Node& node);

/// The mark of a quoted scalar in `doc` whose closing quote is missing, if any. yaml-cpp
/// 0.7 reads an unterminated quote to the end of the document without complaint, which
/// would swallow every key after it.
std::optional<YAML::Mark> unterminatedQuote(const YAML::Node& doc, const std::string& content);

/// One YAML document. A syntax error throws `E` "<source>:<line>: <yaml-cpp's message>".
template <class E>
YAML::Node parseYaml(const std::string& file_content, const std::string& source) {
  // Without a UTF-8 byte order mark, so that yaml-cpp's positions are offsets in `content`.
  const std::string content = file_content.rfind("\xEF\xBB\xBF", 0) == 0 ? file_content.substr(3) : file_content;
  YAML::Node doc;
  try {
    doc = YAML::Load(content);
  } catch (const YAML::Exception& e) {
    throw E(yamlAt(source, e.mark) + ": " + e.msg);
  }
  if (const auto at = unterminatedQuote(doc, content)) throw E(yamlAt(source, *at) + ": quoted text is not closed");
  return doc;
}

/// `map[key]` as a finite number; throws `E` "<source>:<line>: <key> ..." when it is
/// missing or not a number.
template <class E>
double yamlNumberAt(const YAML::Node& map, const char* key, const std::string& source) {
  const YAML::Node n = map[key];
  if (!n) throw E(yamlAt(source, map.Mark()) + ": no '" + key + "' key");
  const std::optional<double> v = yamlNumber(n);
  if (!v) throw E(yamlAt(source, n.Mark()) + ": " + key + " must be a number, got '" + (n.IsScalar() ? n.Scalar() : "") + "'");
  return *v;
}

/// `map[key]` as a sequence of exactly `count` finite numbers; throws `E` naming the key
/// and the line otherwise.
template <class E>
std::vector<double> yamlNumbersAt(const YAML::Node& map, const char* key, size_t count, const std::string& source) {
  const YAML::Node n = map[key];
  if (!n) throw E(yamlAt(source, map.Mark()) + ": no '" + key + "' key");
  const std::string at = yamlAt(source, n.Mark());
  if (!n.IsSequence() || n.size() != count)
    throw E(at + ": " + key + " must be a list of " + std::to_string(count) + " numbers [a, b, ...]");
  std::vector<double> out;
  for (const YAML::Node& item : n) {
    const std::optional<double> v = yamlNumber(item);
    if (!v) throw E(yamlAt(source, item.Mark()) + ": " + key + ": '" + (item.IsScalar() ? item.Scalar() : "") + "' is not a number");
    out.push_back(*v);
  }
  return out;
}

}  // namespace plslam
