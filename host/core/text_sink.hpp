// Text written in pieces: a writer appends to text() and calls piece_done() wherever what it has
// appended so far may go out. Bound to a file (write_text_atomically), the sink writes its text there
// whenever 8 MB have gathered, so that a writer of a multi-million-node mesh holds 8 MB of its file in
// memory, not the whole file; unbound, it keeps the whole text (for the writers' *_string forms).
#pragma once
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

namespace pdmesh {

class TextSink {
 public:
  // How much text gathers before a bound sink writes it.
  static constexpr std::size_t kPiece = std::size_t{8} << 20;

  TextSink() = default;  // unbound: keeps everything
  TextSink(const TextSink&) = delete;
  TextSink& operator=(const TextSink&) = delete;

  std::string& text() { return text_; }
  // A bound sink writes its text when kPiece or more has gathered (InputError naming the file when
  // that fails; Interrupted at a stop request, core/interrupt).
  void piece_done() {
    if (file_ != nullptr && text_.size() >= kPiece) write_out();
  }
  // The whole text of an unbound sink.
  std::string take() { return std::move(text_); }

 private:
  friend void write_text_atomically(const std::filesystem::path& path, const std::function<void(TextSink&)>& write);
  TextSink(std::FILE* file, const std::filesystem::path& path);
  void write_out();
  std::string text_;
  std::FILE* file_ = nullptr;
  std::filesystem::path path_;  // for messages
};

// Creates `path` atomically (core/atomic_file.hpp: a temporary beside it, renamed when complete) from
// the text `write` gives a sink bound to the temporary. Throws InputError naming the path when it
// cannot be written; whatever `write` throws propagates, and the temporary is removed.
void write_text_atomically(const std::filesystem::path& path, const std::function<void(TextSink&)>& write);

}  // namespace pdmesh
