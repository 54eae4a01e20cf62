#include "core/yaml.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>
#include <utility>

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

// Each node once: an alias is the node it names (same mark), and may name the mapping that
// contains it, so without the set a few self-referring aliases make the walk exponential
// (a fuzzed config of 163 bytes ran past libFuzzer's 10 s). Depth-bounded for nodes
// without a mark.
std::optional<YAML::Mark> unterminatedQuoteIn(const YAML::Node& node, const std::string& content, int depth,
                                              std::set<std::pair<int, int>>* seen) {
  if (depth > 64) return std::nullopt;
  const YAML::Mark m = node.Mark();
  // By position and kind: a block mapping starts where its first key does.
  if (!m.is_null() && m.pos >= 0 && !seen->insert({m.pos, static_cast<int>(node.Type())}).second) return std::nullopt;
  if (node.IsScalar()) {
    const bool quoted = !m.is_null() && m.pos >= 0 && static_cast<size_t>(m.pos) < content.size() &&
                        (content[m.pos] == '"' || content[m.pos] == '\'');
    if (quoted && !quoteCloses(content, static_cast<size_t>(m.pos))) return m;
    return std::nullopt;
  }
  if (node.IsMap()) {
    for (const auto& kv : node) {
      if (auto at = unterminatedQuoteIn(kv.first, content, depth + 1, seen)) return at;
      if (auto at = unterminatedQuoteIn(kv.second, content, depth + 1, seen)) return at;
    }
  } else if (node.IsSequence()) {
    for (const YAML::Node& item : node)
      if (auto at = unterminatedQuoteIn(item, content, depth + 1, seen)) return at;
  }
  return std::nullopt;
}

}  // namespace

std::optional<YAML::Mark> unterminatedQuote(const YAML::Node& doc, const std::string& content) {
  std::set<std::pair<int, int>> seen;
  return unterminatedQuoteIn(doc, content, 0, &seen);
}

}  // namespace plslam
