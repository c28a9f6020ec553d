#include "io/xml.h"

#include <cctype>
#include <cstdint>

namespace reel::io {
namespace {

constexpr int kMaxDepth = 64;
constexpr long long kMaxElements = 100'000;

class Parser {
 public:
  explicit Parser(const std::string& s) : s_(s) {}

  Result<XmlElement> document() {
    if (s_.compare(0, 3, "\xEF\xBB\xBF") == 0) at_ = 3;  // a UTF-8 byte-order mark
    skipMisc(true);
    if (failed()) return error();
    if (at_ >= s_.size() || s_[at_] != '<') return fail("expected the root element"), error();
    XmlElement root;
    if (!element(root, 0)) return error();
    skipMisc(false);
    if (failed()) return error();
    if (at_ < s_.size()) return fail("text after the root element"), error();
    return root;
  }

 private:
  bool failed() const { return !message_.empty(); }
  Error error() const { return Error(ErrorKind::BadInput, "line " + std::to_string(line_) + ": " + message_); }
  void fail(const std::string& m) {
    if (message_.empty()) message_ = m;
  }
  void advance(std::size_t n = 1) {
    for (std::size_t i = 0; i < n && at_ < s_.size(); ++i, ++at_)
      if (s_[at_] == '\n') ++line_;
  }
  bool startsWith(const char* p) const { return s_.compare(at_, std::char_traits<char>::length(p), p) == 0; }
  void skipSpace() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) advance();
  }
  // Skips up to and past `end`; false (failed) when it never comes.
  bool skipPast(const char* end, const char* what) {
    const std::size_t p = s_.find(end, at_);
    if (p == std::string::npos) return fail(std::string("unclosed ") + what), false;
    advance(p + std::char_traits<char>::length(end) - at_);
    return true;
  }
  // Whitespace, comments, and (before the root) the declaration and a DOCTYPE.
  void skipMisc(bool prolog) {
    for (;;) {
      skipSpace();
      if (startsWith("<!--")) {
        if (!skipPast("-->", "comment")) return;
      } else if (prolog && startsWith("<?xml")) {
        if (!skipPast("?>", "declaration")) return;
      } else if (prolog && startsWith("<!DOCTYPE")) {
        // A bare DOCTYPE names the root and is skipped; one with declarations ("[ ... ]": entities,
        // the way to expand a file into megabytes or read another) is refused in plain words.
        const std::size_t close = s_.find('>', at_), open = s_.find('[', at_);
        if (open != std::string::npos && (close == std::string::npos || open < close))
          return fail("a DOCTYPE with declarations (entities) is not supported");
        if (!skipPast(">", "DOCTYPE")) return;
      } else if (startsWith("<?")) {
        return fail("processing instructions are not supported");
      } else {
        return;
      }
    }
  }
  static bool nameChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == ':';
  }
  std::string name() {
    const std::size_t b = at_;
    while (at_ < s_.size() && nameChar(s_[at_])) advance();
    return s_.substr(b, at_ - b);
  }
  static void putUtf8(std::string& out, std::uint32_t c) {
    if (c < 0x80) out += static_cast<char>(c);
    else if (c < 0x800) out += static_cast<char>(0xC0 | (c >> 6)), out += static_cast<char>(0x80 | (c & 0x3F));
    else if (c < 0x10000)
      out += static_cast<char>(0xE0 | (c >> 12)), out += static_cast<char>(0x80 | ((c >> 6) & 0x3F)),
          out += static_cast<char>(0x80 | (c & 0x3F));
    else
      out += static_cast<char>(0xF0 | (c >> 18)), out += static_cast<char>(0x80 | ((c >> 12) & 0x3F)),
          out += static_cast<char>(0x80 | ((c >> 6) & 0x3F)), out += static_cast<char>(0x80 | (c & 0x3F));
  }
  // An attribute value between its quotes, entities decoded.
  bool value(std::string& out) {
    if (at_ >= s_.size() || (s_[at_] != '"' && s_[at_] != '\'')) return fail("expected a quoted attribute value"), false;
    const char q = s_[at_];
    advance();
    while (at_ < s_.size() && s_[at_] != q) {
      if (s_[at_] == '<') return fail("'<' in an attribute value"), false;
      if (s_[at_] != '&') {
        out += s_[at_];
        advance();
        continue;
      }
      const std::size_t semi = s_.find(';', at_);
      if (semi == std::string::npos || semi - at_ > 10) return fail("an unfinished entity"), false;
      const std::string e = s_.substr(at_ + 1, semi - at_ - 1);
      if (e == "lt") out += '<';
      else if (e == "gt") out += '>';
      else if (e == "amp") out += '&';
      else if (e == "quot") out += '"';
      else if (e == "apos") out += '\'';
      else if (e.size() > 1 && e[0] == '#') {
        const bool hex = e[1] == 'x';
        std::uint32_t c = 0;
        for (std::size_t i = hex ? 2 : 1; i < e.size(); ++i) {
          const int digit = std::isdigit(static_cast<unsigned char>(e[i])) ? e[i] - '0'
                            : hex && std::isxdigit(static_cast<unsigned char>(e[i])) ? std::tolower(e[i]) - 'a' + 10
                                                                                     : -1;
          if (digit < 0 || c > 0x10FFFF) return fail("a bad character reference &" + e + ";"), false;
          c = c * (hex ? 16 : 10) + static_cast<std::uint32_t>(digit);
        }
        if (c == 0 || c > 0x10FFFF) return fail("a bad character reference &" + e + ";"), false;
        putUtf8(out, c);
      } else {
        return fail("an unknown entity &" + e + ";"), false;
      }
      advance(semi + 1 - at_);
    }
    if (at_ >= s_.size()) return fail("an unclosed attribute value"), false;
    advance();
    return true;
  }
  bool element(XmlElement& e, int depth) {
    if (depth > kMaxDepth) return fail("elements nested deeper than 64"), false;
    if (++elements_ > kMaxElements) return fail("more than 100000 elements"), false;
    e.line = line_;
    advance();  // '<'
    e.name = name();
    if (e.name.empty()) return fail("expected an element name after '<'"), false;
    for (;;) {
      skipSpace();
      if (at_ >= s_.size()) return fail("unclosed tag <" + e.name + ">"), false;
      if (startsWith("/>")) {
        advance(2);
        return true;
      }
      if (s_[at_] == '>') {
        advance();
        break;
      }
      const std::string key = name();
      if (key.empty()) return fail("unexpected '" + std::string(1, s_[at_]) + "' in <" + e.name + ">"), false;
      skipSpace();
      if (at_ >= s_.size() || s_[at_] != '=') return fail("expected '=' after attribute " + key), false;
      advance();
      skipSpace();
      std::string v;
      if (!value(v)) return false;
      if (e.attributes.size() >= 256) return fail("more than 256 attributes in <" + e.name + ">"), false;
      if (e.attribute(key)) return fail("attribute " + key + " given twice in <" + e.name + ">"), false;
      e.attributes.emplace_back(key, std::move(v));
    }
    // Content: child elements, comments, text (ignored), up to the closing tag.
    for (;;) {
      const std::size_t lt = s_.find('<', at_);
      if (lt == std::string::npos) return fail("<" + e.name + "> is never closed"), false;
      advance(lt - at_);
      if (startsWith("<!--")) {
        if (!skipPast("-->", "comment")) return false;
      } else if (startsWith("<![CDATA[")) {
        return fail("CDATA is not supported"), false;
      } else if (startsWith("<?") || startsWith("<!")) {
        return fail("unexpected markup in <" + e.name + ">"), false;
      } else if (startsWith("</")) {
        advance(2);
        const std::string close = name();
        skipSpace();
        if (close != e.name) return fail("</" + close + "> closes <" + e.name + ">"), false;
        if (at_ >= s_.size() || s_[at_] != '>') return fail("expected '>' after </" + close), false;
        advance();
        return true;
      } else {
        e.children.emplace_back();
        if (!element(e.children.back(), depth + 1)) return false;
      }
    }
  }

  const std::string& s_;
  std::size_t at_ = 0;
  int line_ = 1;
  long long elements_ = 0;
  std::string message_;
};

}  // namespace

Result<XmlElement> parseXml(const std::string& text) { return Parser(text).document(); }

}  // namespace reel::io
