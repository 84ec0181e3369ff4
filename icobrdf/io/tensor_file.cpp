#include "icobrdf/io/tensor_file.hpp"

#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"

namespace icobrdf {

namespace {

constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
constexpr std::int64_t kHeaderBytes = 12 + 2 + 4;

std::uint64_t le(const unsigned char* p, int n) {
  std::uint64_t v = 0;
  for (int k = n - 1; k >= 0; --k) v = (v << 8) | p[k];
  return v;
}
void put_le(std::vector<unsigned char>& out, std::uint64_t v, int n) {
  for (int k = 0; k < n; ++k) out.push_back(static_cast<unsigned char>(v >> (8 * k)));
}

double half_to_double(std::uint16_t h) {
  const int sign = h >> 15, exp = (h >> 10) & 0x1f, mant = h & 0x3ff;
  double v;
  if (exp == 0) v = std::ldexp(mant, -24);
  else if (exp == 31) v = mant ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity();
  else v = std::ldexp(mant + 1024, exp - 25);
  return sign ? -v : v;
}

// Reads bytes of the header, with the position named for messages.
struct Cursor {
  const std::vector<unsigned char>& data;
  const std::string& path;
  std::size_t at = 0;
  const unsigned char* take(std::size_t n, const std::string& what) {
    if (data.size() - at < n)
      throw InputError(path + ": tensor file truncated in " + what + ": needs " + std::to_string(n) + " bytes at offset " +
                       std::to_string(at) + ", the file has " + std::to_string(data.size()) + " bytes");
    const unsigned char* p = data.data() + at;
    at += n;
    return p;
  }
};

}  // namespace

int tensor_dtype_bytes(TensorDtype t) {
  switch (t) {
    case TensorDtype::UInt8: case TensorDtype::Int8: return 1;
    case TensorDtype::UInt16: case TensorDtype::Int16: case TensorDtype::Float16: return 2;
    case TensorDtype::UInt32: case TensorDtype::Int32: case TensorDtype::Float32: return 4;
    case TensorDtype::UInt64: case TensorDtype::Int64: case TensorDtype::Float64: return 8;
  }
  return 0;
}

std::string to_string(TensorDtype t) {
  static const char* names[] = {"uint8", "int8", "uint16", "int16", "uint32", "int32", "uint64", "int64", "float16", "float32", "float64"};
  const int k = static_cast<int>(t);
  return k >= 1 && k <= 11 ? names[k - 1] : "dtype " + std::to_string(k);
}

std::uint64_t TensorField::elements() const {
  std::uint64_t n = 1;
  for (auto s : shape) n *= s;
  return n;
}

std::string TensorField::shape_text() const {
  std::string s = "[";
  for (size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
  return s + "]";
}

std::vector<double> TensorField::values() const {
  const std::uint64_t n = elements();
  const int b = tensor_dtype_bytes(dtype);
  std::vector<double> out(static_cast<size_t>(n));
  for (std::uint64_t k = 0; k < n; ++k) {
    const unsigned char* p = bytes.data() + k * b;
    const std::uint64_t u = le(p, b);
    double v = 0;
    switch (dtype) {
      case TensorDtype::UInt8: case TensorDtype::UInt16: case TensorDtype::UInt32: case TensorDtype::UInt64: v = static_cast<double>(u); break;
      case TensorDtype::Int8: v = static_cast<std::int8_t>(u); break;
      case TensorDtype::Int16: v = static_cast<std::int16_t>(u); break;
      case TensorDtype::Int32: v = static_cast<std::int32_t>(static_cast<std::uint32_t>(u)); break;
      case TensorDtype::Int64: v = static_cast<double>(static_cast<std::int64_t>(u)); break;
      case TensorDtype::Float16: v = half_to_double(static_cast<std::uint16_t>(u)); break;
      case TensorDtype::Float32: { const auto w = static_cast<std::uint32_t>(u); float f; std::memcpy(&f, &w, 4); v = f; break; }
      case TensorDtype::Float64: std::memcpy(&v, &u, 8); break;
    }
    out[static_cast<size_t>(k)] = v;
  }
  return out;
}

const TensorField* TensorFile::find(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

TensorFile read_tensor_file(const std::string& path) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path + ": no such tensor file");
  if (!S_ISREG(st.st_mode)) throw InputError(path + ": not a regular file (expected a tensor file)");
  const std::int64_t size = st.st_size;
  if (size < kHeaderBytes)
    throw InputError(path + ": tensor file too short: " + std::to_string(size) + " bytes, expected at least " + std::to_string(kHeaderBytes) +
                     " (magic, version, field count)");
  if (size > kMaxTensorFileBytes)
    throw InputError(path + ": tensor file of " + std::to_string(size) + " bytes exceeds the " + std::to_string(kMaxTensorFileBytes) + "-byte limit");
  std::vector<unsigned char> data(static_cast<size_t>(size));
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open for reading");
    in.read(reinterpret_cast<char*>(data.data()), size);
    if (in.gcount() != size) throw InputError(path + ": read " + std::to_string(in.gcount()) + " of " + std::to_string(size) + " bytes (file changed while reading?)");
  }
  if (std::memcmp(data.data(), kMagic, 12) != 0) {
    std::string found(reinterpret_cast<const char*>(data.data()), 12);
    throw InputError(path + ": not a tensor file: expected the 12-byte magic \"tensor_file\\x00\", found \"" + printable_text(found) + "\"");
  }
  if (data[12] != 1 || data[13] != 0)
    throw InputError(path + ": tensor file version " + std::to_string(data[12]) + "." + std::to_string(data[13]) + " is not supported, expected 1.0");
  const std::uint64_t count = le(data.data() + 14, 4);
  // Each field header takes at least 13 bytes: a count beyond that is corrupt (and would allocate).
  if (count > static_cast<std::uint64_t>(size - kHeaderBytes) / 13)
    throw InputError(path + ": tensor file declares " + std::to_string(count) + " fields, but " + std::to_string(size - kHeaderBytes) +
                     " header bytes hold at most " + std::to_string((size - kHeaderBytes) / 13));
  TensorFile tf;
  tf.path = path;
  Cursor cur{data, path, static_cast<size_t>(kHeaderBytes)};
  std::set<std::string> names;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::string where = "field " + std::to_string(i);
    TensorField f;
    const auto len = static_cast<size_t>(le(cur.take(2, where + " name length"), 2));
    const unsigned char* np = cur.take(len, where + " name");
    f.name.assign(reinterpret_cast<const char*>(np), len);
    const std::string named = where + " '" + quoted_text(f.name) + "'";
    if (f.name.empty()) throw InputError(path + ": " + where + " has an empty name");
    if (!names.insert(f.name).second) throw InputError(path + ": " + named + " appears twice (expected unique field names)");
    const auto ndim = static_cast<size_t>(le(cur.take(2, named + " ndim"), 2));
    const unsigned dtype = *cur.take(1, named + " dtype");
    if (dtype < 1 || dtype > 11)
      throw InputError(path + ": " + named + ": unknown dtype code " + std::to_string(dtype) + ", expected 1..11 (uint8 .. float64)");
    f.dtype = static_cast<TensorDtype>(dtype);
    const std::uint64_t offset = le(cur.take(8, named + " offset"), 8);
    const unsigned char* sp = cur.take(8 * ndim, named + " shape");
    std::uint64_t n = 1;
    bool overflow = false;
    for (size_t d = 0; d < ndim; ++d) {
      const std::uint64_t s = le(sp + 8 * d, 8);
      f.shape.push_back(s);
      if (s != 0 && n > std::numeric_limits<std::uint64_t>::max() / s) overflow = true;
      else n *= s;
    }
    const std::uint64_t eb = static_cast<std::uint64_t>(tensor_dtype_bytes(f.dtype));
    if (overflow || n > static_cast<std::uint64_t>(size) / eb)
      throw InputError(path + ": " + named + ": shape " + f.shape_text() + " of " + to_string(f.dtype) + " needs more bytes than the file's " +
                       std::to_string(size));
    const std::uint64_t bytes = n * eb;
    if (offset > static_cast<std::uint64_t>(size) || bytes > static_cast<std::uint64_t>(size) - offset)
      throw InputError(path + ": " + named + ": data of " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
                       " runs past the end of the file (" + std::to_string(size) + " bytes)");
    f.bytes.assign(data.begin() + static_cast<std::ptrdiff_t>(offset), data.begin() + static_cast<std::ptrdiff_t>(offset + bytes));
    tf.fields.push_back(std::move(f));
  }
  return tf;
}

void write_tensor_file(const std::string& path, const std::vector<TensorField>& fields) {
  std::vector<unsigned char> out(kMagic, kMagic + 12);
  out.push_back(1);
  out.push_back(0);
  put_le(out, fields.size(), 4);
  std::vector<size_t> offset_at;
  for (const auto& f : fields) {
    if (f.name.size() > 65535) throw ArgumentError("tensor field name of " + std::to_string(f.name.size()) + " bytes, at most 65535");
    if (f.bytes.size() != f.elements() * static_cast<std::uint64_t>(tensor_dtype_bytes(f.dtype)))
      throw ArgumentError("tensor field '" + quoted_text(f.name) + "': " + std::to_string(f.bytes.size()) + " bytes for shape " + f.shape_text() +
                          " of " + to_string(f.dtype));
    put_le(out, f.name.size(), 2);
    out.insert(out.end(), f.name.begin(), f.name.end());
    put_le(out, f.shape.size(), 2);
    out.push_back(static_cast<unsigned char>(f.dtype));
    offset_at.push_back(out.size());
    put_le(out, 0, 8);
    for (auto s : f.shape) put_le(out, s, 8);
  }
  for (size_t i = 0; i < fields.size(); ++i) {
    while (out.size() % 8) out.push_back(0);
    const std::uint64_t off = out.size();
    for (int k = 0; k < 8; ++k) out[offset_at[i] + static_cast<size_t>(k)] = static_cast<unsigned char>(off >> (8 * k));
    out.insert(out.end(), fields[i].bytes.begin(), fields[i].bytes.end());
  }
  atomic_write_text(path, std::string(out.begin(), out.end()));
}

namespace {
// A field without data whose shape holds `count` values (ArgumentError otherwise).
TensorField field_for(const std::string& name, TensorDtype dtype, const std::vector<std::uint64_t>& shape, size_t count) {
  TensorField f;
  f.name = name;
  f.dtype = dtype;
  f.shape = shape;
  if (count != f.elements())
    throw ArgumentError("tensor field '" + quoted_text(name) + "': " + std::to_string(count) + " values for shape " + f.shape_text());
  return f;
}
}  // namespace

TensorField float32_field(const std::string& name, const std::vector<std::uint64_t>& shape, const std::vector<double>& values) {
  TensorField f = field_for(name, TensorDtype::Float32, shape, values.size());
  for (double v : values) {
    const float x = static_cast<float>(v);
    std::uint32_t u;
    std::memcpy(&u, &x, 4);
    put_le(f.bytes, u, 4);
  }
  return f;
}

TensorField uint8_field(const std::string& name, const std::vector<std::uint64_t>& shape, const std::vector<std::uint8_t>& values) {
  TensorField f = field_for(name, TensorDtype::UInt8, shape, values.size());
  f.bytes.assign(values.begin(), values.end());
  return f;
}

TensorField text_field(const std::string& name, const std::string& text) {
  return uint8_field(name, {text.size()}, std::vector<std::uint8_t>(text.begin(), text.end()));
}

}  // namespace icobrdf
