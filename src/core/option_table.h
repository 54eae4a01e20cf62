// A table of named, documented options bound to fields of the modules' option structs,
// so that one place applies a configuration file (unknown keys refused, values checked)
// and writes the effective configuration back out with each field's doc line.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace plslam {

/// The bytes of the field a key sets: what lets a test check that every field of an options
/// struct has a key (OptionTable::boundFields).
struct FieldSpan {
  const void* at = nullptr;
  size_t size = 0;
};
template <typename T>
FieldSpan fieldSpan(const T* field) {
  return {field, sizeof(T)};
}

/// The values a number key accepts; a configuration setting one outside is refused with the
/// key's name. Made by atLeast, above and within.
struct Range {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool lo_open = false;  ///< lo itself is refused
  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
  std::string text() const;  ///< ">= 1", "> 0", "in [0, 1]"
};
inline Range atLeast(double lo) { return {lo, HUGE_VAL, false}; }
inline Range above(double lo) { return {lo, HUGE_VAL, true}; }
inline Range within(double lo, double hi) { return {lo, hi, false}; }

class OptionTable {
 public:
  /// Binds `key` (e.g. "tracker.min_inliers") to `*field`. The field's current value is its default.
  void bind(const std::string& key, int* field, const std::string& doc);
  void bind(const std::string& key, double* field, const std::string& doc);
  void bind(const std::string& key, float* field, const std::string& doc);
  void bind(const std::string& key, bool* field, const std::string& doc);
  void bind(const std::string& key, std::string* field, const std::string& doc);
  /// As above, and a value outside `range` is refused.
  void bind(const std::string& key, int* field, const std::string& doc, Range range);
  void bind(const std::string& key, double* field, const std::string& doc, Range range);
  void bind(const std::string& key, float* field, const std::string& doc, Range range);
  /// A random seed (any non-negative whole number).
  void bind(const std::string& key, uint64_t* field, const std::string& doc);
  /// Comma-separated text ("chair, cup"): the list of its non-empty, trimmed items.
  void bindList(const std::string& key, std::vector<std::string>* field, const std::string& doc);
  /// Binds `key` to `field`, a value of the caller's kind: `set` parses the text and throws
  /// std::invalid_argument saying what it expected (the table turns that into a ConfigError
  /// naming the key); `get` gives the value back as text (written quoted). `type` names the
  /// accepted values in messages ("none, replay or yolo").
  void bindCustom(const std::string& key, FieldSpan field, std::function<void(const std::string&)> set,
                  std::function<std::string()> get, const std::string& type, const std::string& doc);

  /// Sets one option from text. Throws ConfigError naming `source` and the key when the key
  /// is unknown or the value does not parse as the field's type.
  void set(const std::string& key, const std::string& value, const std::string& source);
  /// Applies every key of `values` (flat "section.key" names).
  void apply(const std::map<std::string, std::string>& values, const std::string& source);
  bool has(const std::string& key) const { return index_.count(key) > 0; }
  /// The fields bound, in binding order.
  std::vector<FieldSpan> boundFields() const;

  /// The effective configuration as YAML: one section per prefix, a doc comment per key.
  std::string toYaml(const std::string& header_comment = "") const;

 private:
  struct Entry {
    std::string key, doc, type;
    std::function<void(const std::string&)> set;  // throws std::invalid_argument on a bad value
    std::function<std::string()> get;
    FieldSpan field;
  };
  void add(Entry e);
  std::vector<Entry> entries_;
  std::map<std::string, size_t> index_;
};

/// Parses a plslam configuration file (YAML, read by yaml-cpp): nested mappings of scalars
/// ("section:" then indented "key: value"). Returns flat "section.key" -> value; a key
/// without a value sets nothing. Syntax errors, sequences, keys other than letters, digits,
/// '_' and '-', and keys given twice are refused with a ConfigError naming `source` and the line.
std::map<std::string, std::string> parseYamlSubset(const std::string& content, const std::string& source);

/// The non-empty items of a comma-separated list, trimmed of blanks.
std::vector<std::string> splitCommaList(const std::string& list);

/// Throws ConfigError "<section>.<key> must be <range> (got <value>)" unless `ok`: the one
/// message of every options struct's validate().
void requireOption(bool ok, const std::string& section, const std::string& key, const std::string& range, double value);

}  // namespace plslam
