// A text sink that writes its file in pieces; see text_sink.hpp.
#include "core/text_sink.hpp"

#include <cerrno>
#include <cstring>
#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"

namespace pdmesh {

namespace {

[[noreturn]] void cannot_write(const std::filesystem::path& path, int error) {
  throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(error)));
}

}  // namespace

TextSink::TextSink(std::FILE* file, const std::filesystem::path& path) : file_(file), path_(path) {
  // A piece and the longest line or record a writer appends before it calls piece_done() again: the
  // text never reallocates.
  text_.reserve(kPiece + (std::size_t{1} << 20));
}

void TextSink::write_out() {
  if (interrupt_requested()) throw_interrupted();
  if (std::fwrite(text_.data(), 1, text_.size(), file_) != text_.size()) cannot_write(path_, errno);
  text_.clear();
}

void write_text_atomically(const std::filesystem::path& path, const std::function<void(TextSink&)>& write) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) cannot_write(path, errno);
    TextSink sink(f, path);
    try {
      write(sink);
      sink.write_out();
    } catch (...) {
      std::fclose(f);
      throw;
    }
    if (std::fflush(f) != 0) {
      const int e = errno;
      std::fclose(f);
      cannot_write(path, e);
    }
    if (std::fclose(f) != 0) cannot_write(path, errno);
  });
}

}  // namespace pdmesh
