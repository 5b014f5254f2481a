// Text file plumbing shared by the mesh writers and readers: atomic whole-file writes and a
// line/token scanner whose errors name FILE:LINE and the offending text.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/input_file.hpp"

namespace pdmesh {

// Writes `content` to `path` atomically (core/atomic_file.hpp: temporary beside it, then rename).
// Throws InputError naming the path when the directory is missing or not writable.
void write_text_file(const std::filesystem::path& path, const std::string& content);

// Reads a whole file with read_input_file (core/input_file.hpp): regular files only, at most the
// size limit of `kind`, read errors checked; throws InputError naming the path.
std::string read_text_file(const std::filesystem::path& path, InputKind kind = InputKind::Text);

// Walks a text file line by line, splitting lines into whitespace-separated tokens. A UTF-8
// byte-order mark at the start is skipped. Every parse error throws InputError
// "FILE:LINE: what (got 'TEXT')", TEXT quoted by quote_input (at most 100 characters, escaped).
class LineScanner {
 public:
  LineScanner(std::string file_label, std::string content);

  // Next line (trailing '\r' removed), skipping nothing. False at end of file.
  bool next_line(std::string_view& line);
  // Next line that is not blank and whose first non-blank character is not `comment`
  // ('\0' = no comment character). Throws "unexpected end of file, expected WHAT" at the end.
  std::string_view expect_line(std::string_view what, char comment = '\0');
  // Tokens of the next significant line (see expect_line).
  std::vector<std::string_view> expect_tokens(std::string_view what, char comment = '\0');

  // Token mode (files whose records may wrap lines): the next whitespace-separated token,
  // reading further lines as needed; fails "unexpected end of file, expected WHAT" at the end.
  std::string_view token(std::string_view what);
  // The unread remainder of the line the last token came from (trimmed); that line is then done.
  std::string_view rest_of_line();

  // Before allocating by a count read from the file: InputError naming this line, `what` and the
  // count when `count` items of at least `min_bytes_each` bytes cannot fit in the unread text.
  void check_count(long long count, std::size_t min_bytes_each, std::string_view what) const;

  int line() const { return line_; }
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(std::string_view what) const;
  [[noreturn]] void fail(std::string_view what, std::string_view got) const;

  // Parsers that fail with this file and line.
  long long to_int(std::string_view token, std::string_view what) const;
  double to_double(std::string_view token, std::string_view what) const;
  // Index in [lo, hi]; fails naming the range otherwise.
  long long to_index(std::string_view token, long long lo, long long hi, std::string_view what) const;

 private:
  std::string file_;
  std::string content_;
  std::size_t pos_ = 0;
  int line_ = 0;
  std::string_view pending_;  // unread part of the current line in token mode
};

std::vector<std::string_view> split_tokens(std::string_view line);

}  // namespace pdmesh
