#include "core/option_table.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

namespace {

double parseDouble(const std::string& v) {
  char* end = nullptr;
  errno = 0;
  const double d = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || errno != 0 || !std::isfinite(d)) throw std::invalid_argument("expected a number");
  return d;
}

long parseLong(const std::string& v) {
  char* end = nullptr;
  errno = 0;
  const long l = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || errno != 0 || l < -2147483647L || l > 2147483647L)
    throw std::invalid_argument("expected a whole number");
  return l;
}

std::string formatDouble(double d) {
  std::ostringstream os;
  os.precision(10);
  os << d;
  return os.str();
}

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

}  // namespace

void OptionTable::add(Entry e) {
  if (index_.count(e.key)) throw std::logic_error("option bound twice: " + e.key);
  index_[e.key] = entries_.size();
  entries_.push_back(std::move(e));
}

void OptionTable::bind(const std::string& key, int* f, const std::string& doc) {
  add({key, doc, "int", [f](const std::string& v) { *f = static_cast<int>(parseLong(v)); },
       [f] { return std::to_string(*f); }});
}
void OptionTable::bind(const std::string& key, double* f, const std::string& doc) {
  add({key, doc, "number", [f](const std::string& v) { *f = parseDouble(v); }, [f] { return formatDouble(*f); }});
}
void OptionTable::bind(const std::string& key, float* f, const std::string& doc) {
  add({key, doc, "number", [f](const std::string& v) { *f = static_cast<float>(parseDouble(v)); },
       [f] { return formatDouble(*f); }});
}
void OptionTable::bind(const std::string& key, bool* f, const std::string& doc) {
  add({key, doc, "bool",
       [f](const std::string& v) {
         if (v == "true" || v == "yes" || v == "on" || v == "1") *f = true;
         else if (v == "false" || v == "no" || v == "off" || v == "0") *f = false;
         else throw std::invalid_argument("expected true or false");
       },
       [f] { return std::string(*f ? "true" : "false"); }});
}
void OptionTable::bind(const std::string& key, std::string* f, const std::string& doc) {
  add({key, doc, "text", [f](const std::string& v) { *f = v; }, [f] { return "\"" + *f + "\""; }});
}

void OptionTable::set(const std::string& key, const std::string& value, const std::string& source) {
  auto it = index_.find(key);
  if (it == index_.end()) throw ConfigError(source + ": unknown option '" + key + "'");
  Entry& e = entries_[it->second];
  try {
    e.set(value);
  } catch (const std::invalid_argument& ex) {
    throw ConfigError(source + ": option '" + key + "': " + ex.what() + " (" + e.type + "), got '" + value + "'");
  }
}

void OptionTable::apply(const std::map<std::string, std::string>& values, const std::string& source) {
  for (const auto& [k, v] : values) set(k, v, source);
}

std::string OptionTable::toYaml(const std::string& header_comment) const {
  std::ostringstream os;
  if (!header_comment.empty()) os << "# " << header_comment << "\n";
  std::string section;
  for (const Entry& e : entries_) {
    const size_t dot = e.key.find('.');
    const std::string sec = dot == std::string::npos ? "" : e.key.substr(0, dot);
    const std::string name = dot == std::string::npos ? e.key : e.key.substr(dot + 1);
    if (sec != section) {
      os << sec << ":\n";
      section = sec;
    }
    os << (sec.empty() ? "" : "  ") << name << ": " << e.get() << "  # " << e.doc << "\n";
  }
  return os.str();
}

std::map<std::string, std::string> parseYamlSubset(const std::string& content, const std::string& source) {
  std::map<std::string, std::string> out;
  std::vector<std::pair<int, std::string>> stack;  // (indent, key) of open sections
  std::istringstream in(content);
  std::string raw;
  int lineno = 0;
  auto fail = [&](const std::string& what) { throw ConfigError(str(source, ":", lineno, ": ", what)); };
  while (std::getline(in, raw)) {
    ++lineno;
    if (lineno == 1 && raw.rfind("%YAML", 0) == 0) continue;
    if (raw == "---") continue;
    // Strip comments outside quotes.
    std::string line;
    char quote = 0;
    for (char c : raw) {
      if (quote) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '#') {
        break;
      }
      line.push_back(c);
    }
    if (quote) fail("unterminated quote");
    if (trim(line).empty()) continue;
    if (line.find('\t') != std::string::npos && line.find_first_not_of(" \t") > line.find('\t'))
      fail("tabs are not allowed for indentation");
    const int indent = static_cast<int>(line.find_first_not_of(' '));
    const std::string body = trim(line);
    if (body[0] == '-') fail("sequences are not supported in configuration files");
    const size_t colon = body.find(':');
    if (colon == std::string::npos || colon == 0) fail("expected 'key: value' or 'section:'");
    const std::string key = trim(body.substr(0, colon));
    std::string value = trim(body.substr(colon + 1));
    for (char c : key)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) fail("bad key '" + key + "'");
    while (!stack.empty() && stack.back().first >= indent) stack.pop_back();
    if (stack.empty() && indent != 0) fail("unexpected indentation");
    std::string full;
    for (const auto& s : stack) full += s.second + ".";
    full += key;
    if (value.empty()) {
      stack.emplace_back(indent, key);
      continue;
    }
    if (value[0] == '[' || value[0] == '{' || value[0] == '&' || value[0] == '*' || value[0] == '|' || value[0] == '>')
      fail("flow collections, anchors and block scalars are not supported");
    if (value.size() >= 2 && (value[0] == '"' || value[0] == '\'')) {
      if (value.back() != value[0]) fail("text after a quoted value");
      value = value.substr(1, value.size() - 2);
    }
    if (out.count(full)) fail("key '" + full + "' given twice");
    out[full] = value;
  }
  return out;
}

}  // namespace plslam
