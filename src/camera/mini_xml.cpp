#include "camera/mini_xml.h"

#include <cctype>

#include "core/error.h"
#include "core/log.h"

namespace plslam {

const XmlNode* XmlNode::child(const std::string& n) const {
  for (const auto& c : children)
    if (c.name == n) return &c;
  return nullptr;
}

std::vector<const XmlNode*> XmlNode::childrenNamed(const std::string& n) const {
  std::vector<const XmlNode*> out;
  for (const auto& c : children)
    if (c.name == n) out.push_back(&c);
  return out;
}

namespace {

class Parser {
 public:
  Parser(const std::string& s, const std::string& source) : s_(s), source_(source) {}

  XmlNode document() {
    skipMisc();
    if (!startsWith("<")) fail("expected a root element");
    XmlNode root = element(0);
    skipMisc();
    if (pos_ != s_.size()) fail("content after the root element");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw IoError(str(source_, ":", line_, ": malformed XML: ", what)); }
  bool startsWith(const char* p) const { return s_.compare(pos_, std::char_traits<char>::length(p), p) == 0; }
  void advance(size_t n) {
    for (size_t i = 0; i < n && pos_ < s_.size(); ++i)
      if (s_[pos_++] == '\n') ++line_;
  }
  void skipUntil(const char* end) {
    const size_t at = s_.find(end, pos_);
    if (at == std::string::npos) fail(std::string("missing '") + end + "'");
    advance(at - pos_ + std::char_traits<char>::length(end));
  }
  void skipSpace() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) advance(1);
  }
  // Whitespace, comments, processing instructions and doctype between elements.
  void skipMisc() {
    for (;;) {
      skipSpace();
      if (startsWith("<?")) skipUntil("?>");
      else if (startsWith("<!--")) skipUntil("-->");
      else if (startsWith("<!")) skipUntil(">");
      else return;
    }
  }
  std::string name() {
    const size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_' ||
                                s_[pos_] == '-' || s_[pos_] == '.' || s_[pos_] == ':'))
      ++pos_;
    if (start == pos_) fail("expected a name");
    return s_.substr(start, pos_ - start);
  }
  void appendText(std::string* out, const std::string& raw) {
    for (size_t i = 0; i < raw.size(); ++i) {
      if (raw[i] != '&') {
        out->push_back(raw[i]);
        continue;
      }
      static const char* names[] = {"&lt;", "&gt;", "&amp;", "&quot;", "&apos;"};
      static const char chars[] = {'<', '>', '&', '"', '\''};
      bool ok = false;
      for (int k = 0; k < 5 && !ok; ++k)
        if (raw.compare(i, std::char_traits<char>::length(names[k]), names[k]) == 0) {
          out->push_back(chars[k]);
          i += std::char_traits<char>::length(names[k]) - 1;
          ok = true;
        }
      if (!ok) fail("unknown entity");
    }
  }
  XmlNode element(int depth) {
    if (depth > 64) fail("elements nested too deeply");
    XmlNode node;
    node.line = line_;
    advance(1);  // '<'
    node.name = name();
    // Attributes are not used by the formats read here: skip them, quotes respected.
    for (;;) {
      if (pos_ >= s_.size()) fail("unterminated start tag <" + node.name + ">");
      const char c = s_[pos_];
      if (c == '"' || c == '\'') {
        const size_t end = s_.find(c, pos_ + 1);
        if (end == std::string::npos) fail("unterminated attribute value");
        advance(end - pos_ + 1);
      } else if (c == '/' && pos_ + 1 < s_.size() && s_[pos_ + 1] == '>') {
        advance(2);
        return node;
      } else if (c == '>') {
        advance(1);
        break;
      } else {
        advance(1);
      }
    }
    std::string text;
    for (;;) {
      if (pos_ >= s_.size()) fail("element <" + node.name + "> is not closed");
      if (startsWith("<!--")) {
        skipUntil("-->");
      } else if (startsWith("<![CDATA[")) {
        advance(9);
        const size_t end = s_.find("]]>", pos_);
        if (end == std::string::npos) fail("unterminated CDATA");
        text += s_.substr(pos_, end - pos_);
        advance(end - pos_ + 3);
      } else if (startsWith("</")) {
        advance(2);
        const std::string closing = name();
        if (closing != node.name) fail("</" + closing + "> closes <" + node.name + ">");
        skipSpace();
        if (!startsWith(">")) fail("expected '>'");
        advance(1);
        break;
      } else if (startsWith("<?")) {
        skipUntil("?>");
      } else if (startsWith("<")) {
        node.children.push_back(element(depth + 1));
      } else {
        const size_t end = s_.find('<', pos_);
        const size_t stop = end == std::string::npos ? s_.size() : end;
        appendText(&text, s_.substr(pos_, stop - pos_));
        advance(stop - pos_);
      }
    }
    const size_t b = text.find_first_not_of(" \t\r\n");
    const size_t e = text.find_last_not_of(" \t\r\n");
    node.text = b == std::string::npos ? "" : text.substr(b, e - b + 1);
    return node;
  }

  const std::string& s_;
  const std::string& source_;
  size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace

XmlNode parseXml(const std::string& content, const std::string& source) { return Parser(content, source).document(); }

}  // namespace plslam
