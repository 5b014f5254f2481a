// Decoding the contents of VTK XML <DataArray> elements: the binary forms VTK, ParaView and meshio
// write by default ("binary" = base64 inline, "appended" = raw bytes or base64 after <AppendedData>),
// uncompressed or compressed with vtkZLibDataCompressor, with UInt32 or UInt64 block headers, in
// either byte order; and the base64 encoder the writer uses. The ASCII form is parsed by the VTU
// reader itself.
// Format: https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html ("XML File Formats",
// "Binary data" and "Compressed data").
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pdmesh {

// XML's white space (the S production: space, tab, carriage return, line feed).
inline bool is_xml_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

enum class VtuCompressor { None, ZLib };

// File-wide attributes of <VTKFile> that decide how binary arrays are laid out.
struct VtuEncoding {
  bool big_endian = false;     // byte_order="BigEndian"
  bool header_uint64 = false;  // header_type="UInt64" (absent: UInt32, as in file version 0.1)
  VtuCompressor compressor = VtuCompressor::None;
};

// The element type of a DataArray, from its type attribute ("Float64", "Int32", ..., also the
// legacy names "Float", "Int", "UnsignedChar", ...).
struct VtuType {
  int bytes = 0;  // 1, 2, 4 or 8
  bool is_float = false;
  bool is_signed = false;
};
// False for an unknown type name (String, Bit, ...).
bool parse_vtu_type(std::string_view name, VtuType& type);

// Where the bytes of one binary array come from: base64 text (inline or appended, several
// concatenated padded base64 streams allowed, white space ignored) or raw appended bytes.
// Errors throw InputError prefixed with `where` ("FILE:LINE: DataArray 'NAME'").
class VtuBytes {
 public:
  static VtuBytes base64(std::string_view text, std::string where);
  static VtuBytes raw(std::string_view bytes, std::string where);

  // Appends the next n bytes to out; throws when the data ends first (naming `what`).
  void read(std::size_t n, std::vector<unsigned char>& out, std::string_view what);
  // An upper bound on the bytes still available (guards allocations against corrupt headers).
  std::size_t available() const;
  const std::string& where() const { return where_; }

 private:
  VtuBytes(std::string_view text, bool is_base64, std::string where);
  bool next_group();  // decodes the next 4-character base64 group into pending_; false at the end

  std::string_view text_;
  bool base64_ = false;
  std::size_t pos_ = 0;
  unsigned char pending_[3] = {0, 0, 0};
  int pending_count_ = 0;
  int pending_pos_ = 0;
  std::string where_;
};

// Appends the base64 encoding (RFC 4648: the standard alphabet, '=' padding, no line breaks) of the
// bytes put into it to `out`; the writer's half of the "binary" form above. finish() writes the
// last group and must be called once, after the last put().
class Base64Encoder {
 public:
  explicit Base64Encoder(std::string& out) : out_(out) {}
  void put(const void* data, std::size_t n);
  void finish();

 private:
  void flush_whole_groups();
  std::string& out_;
  unsigned char buffer_[3 * 1024];  // bytes not yet encoded; encoded a whole buffer at a time
  std::size_t used_ = 0;
};

// Decodes one binary array (its header, then its possibly compressed blocks) into doubles.
// Throws InputError (prefixed with bytes.where()) on truncated data, a byte count that is not a
// whole number of elements, or a zlib block that does not inflate to its stated size.
std::vector<double> decode_vtu_binary(VtuBytes& bytes, const VtuEncoding& encoding, const VtuType& type);

}  // namespace pdmesh
