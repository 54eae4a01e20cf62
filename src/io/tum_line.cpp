#include "io/tum_line.h"

#include <sstream>

namespace plslam {

bool splitTumLine(const std::string& line, std::vector<std::string>* fields) {
  fields->clear();
  std::string s = line;
  if (!s.empty() && s.back() == '\r') s.pop_back();
  for (char& c : s)
    if (c == ',' || c == '\t') c = ' ';
  const size_t b = s.find_first_not_of(' ');
  if (b == std::string::npos || s[b] == '#') return false;
  std::istringstream is(s);
  for (std::string tok; is >> tok;) fields->push_back(tok);
  // Other whitespace (\v, \f) is not caught above but leaves no field.
  return !fields->empty();
}

}  // namespace plslam
