#include "core/yaml.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace plslam {

std::string yamlAt(const std::string& source, const YAML::Mark& mark) {
  if (mark.is_null()) return source;
  return source + ":" + std::to_string(mark.line + 1);
}

std::optional<double> yamlNumber(const YAML::Node& node) {
  if (!node.IsScalar()) return std::nullopt;
  const std::string& text = node.Scalar();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) return std::nullopt;
  return v;
}

namespace {

// Whether the quoted scalar opening at content[at] has its closing quote.
bool quoteCloses(const std::string& content, size_t at) {
  const char quote = content[at];
  for (size_t i = at + 1; i < content.size(); ++i) {
    if (quote == '"' && content[i] == '\\') {
      ++i;  // an escape: the next character is not the closing quote
    } else if (content[i] == quote) {
      if (quote == '\'' && i + 1 < content.size() && content[i + 1] == '\'') {
        ++i;  // '' is a quote inside single quotes
        continue;
      }
      return true;
    }
  }
  return false;
}

// Depth-bounded: an alias may refer to the mapping that contains it.
std::optional<YAML::Mark> unterminatedQuoteIn(const YAML::Node& node, const std::string& content, int depth) {
  if (depth > 64) return std::nullopt;
  if (node.IsScalar()) {
    const YAML::Mark m = node.Mark();
    const bool quoted = !m.is_null() && m.pos >= 0 && static_cast<size_t>(m.pos) < content.size() &&
                        (content[m.pos] == '"' || content[m.pos] == '\'');
    if (quoted && !quoteCloses(content, static_cast<size_t>(m.pos))) return m;
    return std::nullopt;
  }
  if (node.IsMap()) {
    for (const auto& kv : node) {
      if (auto m = unterminatedQuoteIn(kv.first, content, depth + 1)) return m;
      if (auto m = unterminatedQuoteIn(kv.second, content, depth + 1)) return m;
    }
  } else if (node.IsSequence()) {
    for (const YAML::Node& item : node)
      if (auto m = unterminatedQuoteIn(item, content, depth + 1)) return m;
  }
  return std::nullopt;
}

}  // namespace

std::optional<YAML::Mark> unterminatedQuote(const YAML::Node& doc, const std::string& content) {
  return unterminatedQuoteIn(doc, content, 0);
}

}  // namespace plslam
