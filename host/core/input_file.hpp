// Reading the files a user names, the one way every reader does it: regular files only, within a
// documented size per kind of file, every read checked; plus what readers share when they check
// what they read: a count against the bytes that could hold it, and input text quoted in messages.
// See docs/robustness.md, "Input files".
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace pdmesh {

// What a file is read as: names it in messages and sets its largest accepted size.
enum class InputKind {
  Geometry,    // .crv, .dat, .poly geometry: 1 GiB
  Case,        // case.toml: 1 MiB
  Mesh,        // .msh, .vtu, .su2, Medit .mesh/.sol, Triangle .node/.ele/.poly, also as a spacing data field: 8 GiB
  NodeFile,    // pdmesh node files: 8 GiB
  Checkpoint,  // checkpoint.pdmesh: 8 GiB
  Text,        // anything else pdmesh reads back (timings, tables): 1 GiB
};

// "geometry file", "case file", ...
const char* input_noun(InputKind kind);
// The largest file of that kind that is read, in bytes.
std::uint64_t input_size_limit(InputKind kind);

// The whole file. Throws InputError naming the file when it does not exist or cannot be opened,
// when it is not a regular file (a directory, a device such as /dev/zero, a named pipe, a socket:
// decided with stat() before opening, and the file is opened non-blocking, so a pipe never hangs),
// when it is larger than input_size_limit(kind), and when a read fails.
std::string read_input_file(const std::filesystem::path& path, InputKind kind);

// The extension of `path` with its dot, in lower case (".msh" for "A.MSH"); "" without one. Readers
// are chosen by it.
std::string lower_extension(const std::filesystem::path& path);

// Removes a UTF-8 byte-order mark (EF BB BF) at the start of `text`, as some editors write it.
void skip_utf8_bom(std::string& text);

// Input text as a message shows it: at most `max_chars` characters of it (then "..." and the
// length), printable ASCII as is, a backslash as "\\", every other byte (control characters,
// non-ASCII) as \xNN. So a message never carries invisible or unbounded input.
std::string quote_input(std::string_view text, std::size_t max_chars = 100);

// Throws InputError "WHERE: WHAT COUNT cannot fit in the BYTES bytes left in the file (each needs
// at least MIN)" when `count` items of at least `min_bytes_each` bytes (a line break included, which
// the last item may lack) cannot fit in `bytes_left`.
// Readers call it before they allocate by a count read from a file.
void check_count_fits(std::string_view where, std::string_view what, std::uint64_t count, std::uint64_t bytes_left,
                      std::uint64_t min_bytes_each);

}  // namespace pdmesh
