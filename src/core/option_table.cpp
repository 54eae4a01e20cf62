#include "core/option_table.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "core/log.h"
#include "core/yaml.h"

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

// A YAML double-quoted scalar: the text read back is `text`, whatever it holds.
std::string yamlQuoted(const std::string& text) {
  YAML::Emitter e;
  e << YAML::DoubleQuoted << text;
  return e.c_str();
}

}  // namespace

void OptionTable::add(Entry e) {
  if (index_.count(e.key)) throw std::logic_error("option bound twice: " + e.key);
  // The doc string is the option's only documentation (the struct field has none): required.
  if (e.doc.find_first_not_of(" \t") == std::string::npos || e.doc.find('\n') != std::string::npos)
    throw std::logic_error("option without a one-line doc string: " + e.key);
  index_[e.key] = entries_.size();
  entries_.push_back(std::move(e));
}

void OptionTable::bind(const std::string& key, int* f, const std::string& doc) {
  add({key, doc, "int", [f](const std::string& v) { *f = static_cast<int>(parseLong(v)); },
       [f] { return std::to_string(*f); }, fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, double* f, const std::string& doc) {
  add({key, doc, "number", [f](const std::string& v) { *f = parseDouble(v); }, [f] { return formatDouble(*f); },
       fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, float* f, const std::string& doc) {
  add({key, doc, "number", [f](const std::string& v) { *f = static_cast<float>(parseDouble(v)); },
       [f] { return formatDouble(*f); }, fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, bool* f, const std::string& doc) {
  add({key, doc, "bool",
       [f](const std::string& v) {
         if (v == "true" || v == "yes" || v == "on" || v == "1") *f = true;
         else if (v == "false" || v == "no" || v == "off" || v == "0") *f = false;
         else throw std::invalid_argument("expected true or false");
       },
       [f] { return std::string(*f ? "true" : "false"); }, fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, std::string* f, const std::string& doc) {
  add({key, doc, "text", [f](const std::string& v) { *f = v; }, [f] { return yamlQuoted(*f); }, fieldSpan(f)});
}

std::string Range::text() const {
  if (std::isinf(hi)) return str(lo_open ? "> " : ">= ", lo);
  return str("in ", lo_open ? "(" : "[", lo, ", ", hi, "]");
}

namespace {
// The parsed value when `range` holds it; else what the key expects.
double checked(double v, const Range& range, const char* kind) {
  if (!range.contains(v)) throw std::invalid_argument(str("expected ", kind, " ", range.text()));
  return v;
}
}  // namespace

void OptionTable::bind(const std::string& key, int* f, const std::string& doc, Range range) {
  add({key, doc, "int", [f, range](const std::string& v) { *f = static_cast<int>(checked(parseLong(v), range, "a whole number")); },
       [f] { return std::to_string(*f); }, fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, double* f, const std::string& doc, Range range) {
  add({key, doc, "number", [f, range](const std::string& v) { *f = checked(parseDouble(v), range, "a number"); },
       [f] { return formatDouble(*f); }, fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, float* f, const std::string& doc, Range range) {
  add({key, doc, "number",
       [f, range](const std::string& v) { *f = static_cast<float>(checked(parseDouble(v), range, "a number")); },
       [f] { return formatDouble(*f); }, fieldSpan(f)});
}
void OptionTable::bind(const std::string& key, uint64_t* f, const std::string& doc) {
  add({key, doc, "int",
       [f](const std::string& v) {
         char* end = nullptr;
         errno = 0;
         const unsigned long long u = std::strtoull(v.c_str(), &end, 10);
         if (v.empty() || v[0] == '-' || *end != '\0' || errno != 0) throw std::invalid_argument("expected a whole number >= 0");
         *f = static_cast<uint64_t>(u);
       },
       [f] { return std::to_string(*f); }, fieldSpan(f)});
}
void OptionTable::bindList(const std::string& key, std::vector<std::string>* f, const std::string& doc) {
  add({key, doc, "text", [f](const std::string& v) { *f = splitCommaList(v); },
       [f] {
         std::string joined;
         for (const std::string& item : *f) joined += (joined.empty() ? "" : ", ") + item;
         return yamlQuoted(joined);
       },
       fieldSpan(f)});
}

std::vector<std::string> splitCommaList(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    const size_t b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b != std::string::npos) items.push_back(item.substr(b, e - b + 1));
  }
  return items;
}

void OptionTable::bindCustom(const std::string& key, FieldSpan field, std::function<void(const std::string&)> set,
                             std::function<std::string()> get, const std::string& type, const std::string& doc) {
  add({key, doc, type, std::move(set), [get = std::move(get)] { return yamlQuoted(get()); }, field});
}

std::vector<FieldSpan> OptionTable::boundFields() const {
  std::vector<FieldSpan> out;
  for (const Entry& e : entries_) out.push_back(e.field);
  return out;
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
  // Keys are grouped by section in the order sections first appear: a section bound in two
  // places must still be one mapping (YAML readers refuse or overwrite a repeated key).
  const auto sectionOf = [](const Entry& e) {
    const size_t dot = e.key.find('.');
    return dot == std::string::npos ? std::string() : e.key.substr(0, dot);
  };
  std::vector<std::string> sections;
  for (const Entry& e : entries_)
    if (std::find(sections.begin(), sections.end(), sectionOf(e)) == sections.end()) sections.push_back(sectionOf(e));
  for (const std::string& sec : sections) {
    if (!sec.empty()) os << sec << ":\n";
    for (const Entry& e : entries_) {
      if (sectionOf(e) != sec) continue;
      const std::string name = sec.empty() ? e.key : e.key.substr(sec.size() + 1);
      os << (sec.empty() ? "" : "  ") << name << ": " << e.get() << "  # " << e.doc << "\n";
    }
  }
  return os.str();
}

namespace {

bool validKey(const std::string& key) {
  if (key.empty()) return false;
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

// Adds the scalars of `map` to `out` as "prefix.key" -> text, descending into nested
// mappings. The depth bound also stops an alias that refers to its own mapping.
void flattenMapping(const YAML::Node& map, const std::string& prefix, int depth, const std::string& source,
                    std::map<std::string, std::string>* out) {
  const auto fail = [&](const YAML::Node& at, const std::string& what) { throw ConfigError(yamlAt(source, at.Mark()) + ": " + what); };
  if (depth > 8) fail(map, "mappings nested too deep");
  for (const auto& kv : map) {
    const YAML::Node& key = kv.first;
    const YAML::Node& value = kv.second;
    if (!key.IsScalar() || !validKey(key.Scalar()))
      fail(key, "bad key '" + (key.IsScalar() ? key.Scalar() : std::string("(not text)")) + "'");
    const std::string full = prefix + key.Scalar();
    if (value.IsMap()) {
      flattenMapping(value, full + ".", depth + 1, source, out);
    } else if (value.IsSequence()) {
      fail(value, "'" + full + "': sequences are not supported in configuration files");
    } else if (value.IsScalar()) {
      if (!out->emplace(full, value.Scalar()).second) fail(key, "key '" + full + "' given twice");
    }
    // A key without a value ("section:" with nothing under it) sets nothing.
  }
}

}  // namespace

std::map<std::string, std::string> parseYamlSubset(const std::string& content, const std::string& source) {
  const YAML::Node doc = parseYaml<ConfigError>(content, source);
  std::map<std::string, std::string> out;
  if (doc.IsNull()) return out;  // empty, or only comments
  if (!doc.IsMap()) throw ConfigError(yamlAt(source, doc.Mark()) + ": expected 'key: value' or 'section:' lines");
  flattenMapping(doc, "", 0, source, &out);
  return out;
}

void requireOption(bool ok, const std::string& section, const std::string& key, const std::string& range, double value) {
  if (!ok) throw ConfigError(str(section, ".", key, " must be ", range, " (got ", value, ")"));
}

}  // namespace plslam
