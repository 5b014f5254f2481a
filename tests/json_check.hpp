// A strict JSON syntax check for the tests of files pdmesh writes (--timings, quality.json): RFC 8259
// values, no trailing commas, no NaN or Infinity, nothing after the top-level value. A checker only:
// the tests read the values they need by other means.
#pragma once
#include <cctype>
#include <cstddef>
#include <string>

namespace pdmesh_test {

class JsonCheck {
 public:
  // True when `text` is one well-formed JSON value (surrounded by white space at most); otherwise
  // false, with error() saying where.
  bool valid(const std::string& text) {
    s_ = &text;
    i_ = 0;
    error_.clear();
    space();
    if (!value()) return false;
    space();
    if (i_ != text.size()) return fail("text after the value");
    return true;
  }
  const std::string& error() const { return error_; }

 private:
  bool fail(const char* what) {
    if (error_.empty()) error_ = std::string(what) + " at offset " + std::to_string(i_);
    return false;
  }
  bool at_end() const { return i_ >= s_->size(); }
  char peek() const { return at_end() ? '\0' : (*s_)[i_]; }
  void space() {
    while (!at_end() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) ++i_;
  }
  bool literal(const char* word) {
    const std::string w(word);
    if (s_->compare(i_, w.size(), w) != 0) return fail("unknown literal");
    i_ += w.size();
    return true;
  }
  bool value() {
    switch (peek()) {
      case '{':
        return members('}', true);
      case '[':
        return members(']', false);
      case '"':
        return string();
      case 't':
        return literal("true");
      case 'f':
        return literal("false");
      case 'n':
        return literal("null");
      default:
        return number();
    }
  }
  // An object (keyed members) or an array: values separated by ',' up to `close`.
  bool members(char close, bool keyed) {
    ++i_;
    space();
    if (peek() == close) return ++i_, true;
    for (;;) {
      space();
      if (keyed) {
        if (peek() != '"' || !string()) return fail("expected a key");
        space();
        if (peek() != ':') return fail("expected ':'");
        ++i_;
        space();
      }
      if (!value()) return false;
      space();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() == close) return ++i_, true;
      return fail(keyed ? "expected ',' or '}'" : "expected ',' or ']'");
    }
  }
  bool string() {
    ++i_;
    while (!at_end()) {
      const unsigned char c = static_cast<unsigned char>(peek());
      if (c == '"') return ++i_, true;
      if (c < 0x20) return fail("control character in a string");
      if (c == '\\') {
        ++i_;
        const char e = peek();
        if (e == 'u') {
          for (int k = 1; k <= 4; ++k)
            if (!std::isxdigit(static_cast<unsigned char>(i_ + k < s_->size() ? (*s_)[i_ + k] : 'x')))
              return fail("bad \\u escape");
          i_ += 4;
        } else if (std::string("\"\\/bfnrt").find(e) == std::string::npos || e == '\0') {
          return fail("bad escape");
        }
      }
      ++i_;
    }
    return fail("unterminated string");
  }
  bool digits() {
    const std::size_t start = i_;
    while (std::isdigit(static_cast<unsigned char>(peek()))) ++i_;
    return i_ > start;
  }
  bool number() {
    if (peek() == '-') ++i_;
    if (peek() == '0') {
      ++i_;
    } else if (!digits()) {
      return fail("expected a value");
    }
    if (peek() == '.') {
      ++i_;
      if (!digits()) return fail("expected digits after '.'");
    }
    if (peek() == 'e' || peek() == 'E') {
      ++i_;
      if (peek() == '+' || peek() == '-') ++i_;
      if (!digits()) return fail("expected exponent digits");
    }
    return true;
  }

  const std::string* s_ = nullptr;
  std::size_t i_ = 0;
  std::string error_;
};

}  // namespace pdmesh_test
