// The one JSON helper the writers share: a string as a JSON literal.
#pragma once

#include <string>

namespace plslam {

/// `text` as a JSON string literal: quotes added, quotes, backslashes and control
/// characters escaped.
std::string jsonQuote(const std::string& text);

}  // namespace plslam
