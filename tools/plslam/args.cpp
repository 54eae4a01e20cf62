#include "args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "core/error.h"

namespace plslam::cli {

Args& Args::option(const std::string& name, const std::string& help, const std::string& fallback, bool required) {
  order_.push_back(name);
  specs_[name] = Spec{help, fallback, false, required};
  return *this;
}

Args& Args::flag(const std::string& name, const std::string& help) {
  order_.push_back(name);
  specs_[name] = Spec{help, "", true, false};
  return *this;
}

bool Args::parse(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << help();
      return false;
    }
    if (a.rfind("--", 0) != 0)
      throw ConfigError("plslam " + command_ + ": unexpected argument '" + a + "' (see plslam " + command_ + " --help)");
    std::string name = a.substr(2), value;
    bool inline_value = false;
    if (const size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      inline_value = true;
    }
    auto it = specs_.find(name);
    if (it == specs_.end())
      throw ConfigError("plslam " + command_ + ": unknown option --" + name + " (see plslam " + command_ + " --help)");
    if (it->second.is_flag) {
      if (inline_value) throw ConfigError("plslam " + command_ + ": --" + name + " takes no value");
      values_[name] = "1";
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= argc) throw ConfigError("plslam " + command_ + ": --" + name + " needs a value");
      value = argv[++i];
    }
    values_[name] = value;
  }
  for (const auto& [name, spec] : specs_)
    if (spec.required && !values_.count(name))
      throw ConfigError("plslam " + command_ + ": --" + name + " is required (see plslam " + command_ + " --help)");
  return true;
}

bool Args::has(const std::string& name) const { return values_.count(name) > 0; }

std::string Args::str(const std::string& name) const {
  auto v = values_.find(name);
  if (v != values_.end()) return v->second;
  auto s = specs_.find(name);
  return s == specs_.end() ? std::string() : s->second.fallback;
}

double Args::number(const std::string& name) const {
  const std::string s = str(name);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || errno != 0 || !std::isfinite(v))
    throw ConfigError("plslam " + command_ + ": --" + name + " expects a number, got '" + s + "'");
  return v;
}

int Args::integer(const std::string& name, int min_value, int max_value) const {
  const std::string s = str(name);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || errno != 0 || v < min_value || v > max_value) {
    std::ostringstream os;
    os << "plslam " << command_ << ": --" << name << " expects a whole number in [" << min_value << ", " << max_value
       << "], got '" << s << "'";
    throw ConfigError(os.str());
  }
  return static_cast<int>(v);
}

std::string Args::help() const {
  std::ostringstream os;
  os << "usage: plslam " << command_ << " [options]\n\n" << summary_ << "\n\noptions:\n";
  for (const auto& name : order_) {
    const Spec& s = specs_.at(name);
    std::string left = "  --" + name + (s.is_flag ? "" : " VALUE");
    if (left.size() < 26) left.resize(26, ' ');
    else left += "\n" + std::string(26, ' ');
    os << left << s.help;
    if (s.required) os << " (required)";
    else if (!s.fallback.empty()) os << " [default: " << s.fallback << "]";
    os << "\n";
  }
  os << "  --help                  this text\n";
  if (!epilog_.empty()) os << "\n" << epilog_ << "\n";
  return os.str();
}

}  // namespace plslam::cli
