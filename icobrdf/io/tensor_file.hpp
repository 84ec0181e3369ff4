#pragma once
// The tensor file format of Mitsuba (the container of the RGL measured-BRDF database, icobrdf/io/rgl_bsdf.hpp):
// named, typed n-dimensional arrays. Little-endian throughout:
//   12 bytes  "tensor_file\0"
//   2 bytes   version major, minor = 1, 0
//   uint32    field count F
//   F field headers, each: uint16 name length L, L bytes name (UTF-8, no terminator), uint16 ndim,
//             uint8 dtype, uint64 offset of the data from the start of the file, ndim x uint64 shape
//   the data of each field: prod(shape) elements of dtype, C order (last index contiguous), at its offset
//   (the writer aligns each block to 8 bytes; readers accept any offset).
// dtype codes: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64, 9 float16,
// 10 float32, 11 float64.
//
// read_tensor_file checks everything it reads and throws InputError with one line naming the file, the
// field (by index and name) and expected vs found: a file shorter than the 18-byte header, a wrong magic or
// version, a field header running past the end of the file, an unknown dtype, a duplicate or empty name, an
// element count that overflows, and a data block outside the file. Fields whose data overlap are accepted
// (nothing forbids sharing). The whole file is read into memory (a file at most kMaxTensorFileBytes).
#include <cstdint>
#include <string>
#include <vector>

namespace icobrdf {

enum class TensorDtype : std::uint8_t {
  UInt8 = 1, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64
};
int tensor_dtype_bytes(TensorDtype t);
std::string to_string(TensorDtype t);

// Largest tensor file read (the RGL database's spectral files are tens of MB).
inline constexpr std::int64_t kMaxTensorFileBytes = std::int64_t(1) << 32;

struct TensorField {
  std::string name;
  TensorDtype dtype = TensorDtype::Float32;
  std::vector<std::uint64_t> shape;
  std::vector<unsigned char> bytes;  // prod(shape) * tensor_dtype_bytes(dtype) bytes, little-endian
  std::uint64_t elements() const;
  std::string shape_text() const;     // "[8, 3, 32, 32]"
  // Elements as doubles (float16 decoded exactly; 64-bit integers above 2^53 round).
  std::vector<double> values() const;
};

struct TensorFile {
  std::string path;
  std::vector<TensorField> fields;  // in file order
  const TensorField* find(const std::string& name) const;  // nullptr when absent
};

TensorFile read_tensor_file(const std::string& path);

// Writes fields in the order given, each data block aligned to 8 bytes; atomic (icobrdf/io/atomic_write.hpp).
// ArgumentError for a field whose bytes disagree with its shape and dtype, or a name over 65535 bytes.
void write_tensor_file(const std::string& path, const std::vector<TensorField>& fields);

// Field constructors for writers (tests, tools).
TensorField float32_field(const std::string& name, const std::vector<std::uint64_t>& shape, const std::vector<double>& values);
TensorField uint8_field(const std::string& name, const std::vector<std::uint64_t>& shape, const std::vector<std::uint8_t>& values);
TensorField text_field(const std::string& name, const std::string& text);  // uint8, shape [size]

}  // namespace icobrdf
