#pragma once
// h5: a small RAII layer over the HDF5 C API (Debian's HDF5 1.10) for the files icobrdf writes.
//
// Writing: WriteFile creates a file (only ever a fresh temporary, see icobrdf/io/atomic_write.hpp), Group writes
// attributes and datasets with a unit attribute on every numeric dataset. Non-empty datasets are chunked
// and carry a Fletcher32 checksum; those of at least kCompressMinBytes are also shuffled and deflated.
// Objects keep up to 64 attributes in their headers (HDF5 moves more than 8 to a slower dense store by
// default) and chunk indexes use B-tree nodes of 2 x 8 entries (default 2 x 32): with the compression
// threshold below, a bank of 1,000 small materials is written 2x faster than with HDF5's defaults and is
// 7% smaller. The file format stays readable by HDF5 1.8 and later.
// Write failures throw IoError.
//
// Reading: ReadFile / Group check, BEFORE allocating, that an object is reached by a hard link (soft,
// external and user-defined links are refused), is of the expected kind, has the expected element type
// (class and size), rank and shape, declares at most ReadLimits::max_dataset_bytes, uses no external or
// virtual storage and only the deflate / shuffle / Fletcher32 filters. Fletcher32 checksums are verified
// on every read. Any violation throws InputError with one line "<file>: <object path>: <what>, expected
// <x>, found <y>".
//
// Shapes are logical row-major shapes, as HDF5 and numpy store them.
// HDF5's automatic error printing and dynamic filter plugins are disabled process-wide by h5::init(),
// which every entry point calls; HDF5's own error text is folded into our one-line messages instead.
// Not thread-safe: the Debian HDF5 build serializes nothing, so call from one thread at a time.
#include <hdf5.h>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace icobrdf::h5 {

// Disables HDF5's automatic error-stack printing (nothing but our one-line errors reaches stderr) and the
// loading of filter plugins named by a file. Idempotent; called by every entry point below.
void init();

// For programs, before any other HDF5 call: HDF5 registers no exit handler (H5dont_atexit). A file whose
// close failed (a write refused on a full disk or over the file-size limit) stays in HDF5's table, and
// HDF5 1.10's exit handler then crashes closing it again (SIGSEGV in H5F__close_cb, exit 139 after the
// program's own error line). The program closes every file it opens, so at exit the handler has nothing
// left to flush; unwritten temporaries are removed by their owners (atomic_write). Not for the Python
// module: other users of the same HDF5 in that process (h5py) may rely on the handler.
void leave_library_at_exit();

// The innermost message on HDF5's current error stack ("" when empty), then clears the stack.
std::string take_error_detail();

// Owns one HDF5 identifier; closes it with the matching H5*close function.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*closer)(hid_t)) : id_(id), closer_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept;
  ~Handle() { close(); }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes now; returns the close function's status (0 when nothing was open).
  herr_t close();

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*closer_)(hid_t) = nullptr;
};

using Shape = std::vector<std::uint64_t>;  // logical row-major shape
std::string shape_text(const Shape& s);    // "3 x 6 x 6"; "scalar" for rank 0

// Element types stored in the files (all little-endian on disk; big-endian files are read too).
enum class Type { float64, float32, int32, int64, uint8, int16, int8 };
const char* type_name(Type t);
template <class T> struct TypeOf;
template <> struct TypeOf<double> { static constexpr Type value = Type::float64; };
template <> struct TypeOf<float> { static constexpr Type value = Type::float32; };
template <> struct TypeOf<std::int32_t> { static constexpr Type value = Type::int32; };
template <> struct TypeOf<std::int64_t> { static constexpr Type value = Type::int64; };
template <> struct TypeOf<std::uint8_t> { static constexpr Type value = Type::uint8; };
template <> struct TypeOf<std::int16_t> { static constexpr Type value = Type::int16; };
template <> struct TypeOf<std::int8_t> { static constexpr Type value = Type::int8; };

// Datasets of at least this many bytes are shuffled and deflated as well as checksummed. Below it deflate
// saves little on float64 data and costs much: at 4 KiB it was 40% of writing a bank of 1,000 order-6
// materials (6 KB of coefficients each; benchmarks/RESULTS.md, "Writing banks").
inline constexpr std::uint64_t kCompressMinBytes = 65536;
// Chunks hold at most this many bytes (whole trailing rows): large enough for fast I/O, small enough
// that reading one row of a LUT does not inflate the whole dataset.
inline constexpr std::uint64_t kChunkTargetBytes = 1u << 20;
// deflate level: 4 is near the knee of zlib's size/time curve for float64 data.
inline constexpr unsigned kDeflateLevel = 4;
// Default largest dataset a read accepts (4 GiB: a level-5 float64 LUT with 3 channels is 2.5 GB).
inline constexpr std::uint64_t kDefaultMaxDatasetBytes = std::uint64_t{1} << 32;
// Longest string attribute a read accepts.
inline constexpr std::uint64_t kMaxStringBytes = 1u << 16;
// Most links a read accepts in one group.
inline constexpr std::uint64_t kMaxGroupLinks = 100000;

struct ReadLimits {
  std::uint64_t max_dataset_bytes = kDefaultMaxDatasetBytes;
};

// Reads of one object (a stored material) are held to the memory budget (icobrdf/core/support/
// memory_budget.hpp) before they allocate: while a ReadScope lives on this thread, every dataset read adds
// the bytes it takes in memory (and, for a stored type other than float64, the float64 copy its reader
// makes), and a read that takes the sum beyond available_memory() is refused with a ResourceError naming the
// dataset and its declared shape. A 1 MB file can declare gigabytes of compressed zeros. Outside a scope a
// single dataset is held to the budget alone. Sums below kBudgetCheckBytes are not checked (no /proc read).
inline constexpr std::uint64_t kBudgetCheckBytes = std::uint64_t{64} << 20;
class ReadScope {
 public:
  ReadScope();
  ~ReadScope();
  ReadScope(const ReadScope&) = delete;
  ReadScope& operator=(const ReadScope&) = delete;

 private:
  bool outer_active_;
  std::uint64_t outer_bytes_;
};

// A shape pattern for reads: -1 matches any extent.
using ShapePattern = std::vector<std::int64_t>;

template <class T>
struct Array {
  Shape shape;
  std::vector<T> data;  // row-major
};

// A group (or the root group) of an open file. Carries the file path and the object path for messages.
class Group {
 public:
  Group(Handle h, std::string file, std::string path) : h_(std::move(h)), file_(std::move(file)), path_(std::move(path)) {}
  hid_t id() const { return h_.get(); }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  std::string child_path(const std::string& name) const;

  // ---- writing (IoError on failure) ----
  Group create_group(const std::string& name);
  void set_attr(const std::string& name, const std::string& value);
  void set_attr(const std::string& name, const char* value) { set_attr(name, std::string(value)); }
  void set_attr(const std::string& name, double value);
  void set_attr(const std::string& name, std::int32_t value);
  void set_attr(const std::string& name, std::int64_t value);
  void set_attr(const std::string& name, bool value);  // stored as uint8 0 / 1
  // Writes a dataset of the given logical shape with attributes unit and (when non-empty) description.
  template <class T>
  void write(const std::string& name, const T* data, const Shape& shape, const std::string& unit,
             const std::string& description = "");
  // A matrix as a rows x cols float64 dataset (row-major on disk whatever Eigen's storage order).
  void write_matrix(const std::string& name, const Eigen::MatrixXd& m, const std::string& unit,
                    const std::string& description = "");

  // ---- reading (InputError on anything unexpected) ----
  // Every link of this group is a hard link; throws naming the first that is not.
  void check_links() const;
  // Names of the links in this group, in name order (at most kMaxGroupLinks).
  std::vector<std::string> children() const;
  // True when `name` exists (as a hard link; other link kinds throw).
  bool has(const std::string& name) const;
  bool is_group(const std::string& name) const;  // requires has(name)
  Group open_group(const std::string& name) const;
  // A view of dataset (or group) `name` for reading its attributes with the attr_* members.
  Group attributes_of(const std::string& name) const;
  bool has_attr(const std::string& name) const;
  std::string attr_string(const std::string& name) const;
  double attr_double(const std::string& name) const;
  std::int64_t attr_int(const std::string& name, std::int64_t lo, std::int64_t hi) const;  // int32 or int64, in [lo, hi]
  bool attr_bool(const std::string& name) const;                                           // uint8 0 or 1
  // Element type and shape of a dataset, after the storage / filter / limit checks.
  Type dataset_type(const std::string& name, const ReadLimits& limits) const;
  Shape dataset_shape(const std::string& name, const ReadLimits& limits) const;
  // Reads a dataset of element type T (exactly: class and size) matching `pattern`.
  template <class T>
  Array<T> read(const std::string& name, const ShapePattern& pattern, const ReadLimits& limits) const;
  // Reads a float64 or float32 dataset into doubles.
  Array<double> read_real(const std::string& name, const ShapePattern& pattern, const ReadLimits& limits) const;

  // Throws InputError "<file>: <object>: <what>".
  [[noreturn]] void fail(const std::string& object, const std::string& what) const;

 private:
  Handle open_dataset_checked(const std::string& name, const ReadLimits& limits, Shape* shape, Handle* type) const;
  void write_raw(const std::string& name, Type type, const void* data, const Shape& shape, const std::string& unit,
                 const std::string& description);
  void read_raw(const std::string& name, Type type, bool allow_float32, const ShapePattern& pattern,
                const ReadLimits& limits, Shape* shape, void* (*alloc)(void*, std::uint64_t), void* vec) const;

  friend class WriteFile;
  Handle h_;
  std::string file_;
  std::string path_;
  bool compress_ = true;  // deflate large datasets (false in in-memory files: WriteFile::create_in_memory)
};

// A file being written. Create it only on a fresh path you own (a temporary): it is truncated.
// Messages name `display_path` (the destination the temporary will be renamed to).
class WriteFile {
 public:
  static WriteFile create(const std::string& path, const std::string& display_path);
  // A file in memory only (HDF5's core driver without a backing store): nothing touches the file system;
  // finish_image() gives its bytes. `display_path` names it in messages. Its datasets are checksummed but not
  // deflated: such a file is a message to another process, which spends less time on the bytes than deflate.
  static WriteFile create_in_memory(const std::string& display_path);
  Group root();
  // Flushes all buffers to the OS, then writes the root attribute complete = 1, then closes.
  // IoError on any failure (e.g. disk full).
  void finish();
  // The same for a file made by create_in_memory: its complete bytes (what a file on disk would hold).
  std::string finish_image();
  const std::string& path() const { return path_; }

 private:
  WriteFile(Handle f, std::string path) : f_(std::move(f)), path_(std::move(path)) {}
  Handle f_;
  std::string path_;
  bool compress_ = true;
};

// A file opened read-only. IoError when the file system refuses; InputError when it is not a readable
// HDF5 file.
class ReadFile {
 public:
  static ReadFile open(const std::string& path);
  // The bytes of a file (WriteFile::finish_image), read from memory with the same checks; `display_path`
  // names it in messages. InputError when they are not an HDF5 file.
  static ReadFile open_image(const std::string& bytes, const std::string& display_path);
  Group root() const;
  const std::string& path() const { return path_; }

 private:
  ReadFile(Handle f, std::string path) : f_(std::move(f)), path_(std::move(path)) {}
  Handle f_;
  std::string path_;
};

// ---- template definitions ----
template <class T>
void Group::write(const std::string& name, const T* data, const Shape& shape, const std::string& unit,
                  const std::string& description) {
  write_raw(name, TypeOf<T>::value, data, shape, unit, description);
}

template <class T>
Array<T> Group::read(const std::string& name, const ShapePattern& pattern, const ReadLimits& limits) const {
  Array<T> out;
  read_raw(name, TypeOf<T>::value, false, pattern, limits, &out.shape,
           [](void* v, std::uint64_t n) -> void* {
             auto* vec = static_cast<std::vector<T>*>(v);
             vec->resize(n);
             return vec->data();
           },
           &out.data);
  return out;
}

}  // namespace icobrdf::h5
