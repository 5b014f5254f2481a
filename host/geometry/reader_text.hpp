// Text handling shared by the geometry file readers: load a file as checked text, split it into
// numbered token lines without blanks and '#' comments, and parse numbers with exact messages.
#pragma once
#include <string>
#include <vector>

namespace pdmesh::detail {

struct TokenLine {
  int number = 0;                   // 1-based line number in the file
  std::vector<std::string> tokens;  // whitespace-separated, comment removed; never empty
};

// Throws InputError when the file cannot be read or is not text (a NUL or other control byte).
// Blank lines and everything from '#' to the end of a line are dropped.
std::vector<TokenLine> read_token_lines(const std::string& path);

// A finite coordinate with |v| <= 1e150; InputError "FILE:LINE: ..." naming the token otherwise.
double parse_coordinate(const std::string& file, int line, const std::string& token, const char* what);
// A non-negative integer (a count or an index); InputError naming the token otherwise.
long long parse_count(const std::string& file, int line, const std::string& token, const char* what);

// Any integer (a boundary marker); InputError naming the token otherwise.
long long parse_integer(const std::string& file, int line, const std::string& token, const char* what);

}  // namespace pdmesh::detail
