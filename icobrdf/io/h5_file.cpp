#include "icobrdf/io/h5_file.hpp"

#include <H5PLpublic.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <utility>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"

namespace icobrdf::h5 {

namespace {

// Attributes an object keeps in its header before HDF5 moves them to a separate dense store (HDF5's
// default is 8; a material group has about 20, and the dense store made every attribute write 2x slower).
constexpr unsigned kMaxCompactAttributes = 64;
// Half the fan-out of a chunked dataset's index B-tree node (HDF5's default is 32). Every chunked dataset
// gets one node, sized for 2K entries however few chunks it has: at 32 that node outweighed the small
// datasets of a bank (a bank of 1,000 order-6 materials was 20.6 MB, 14.4 MB at 8). At 8 a level-5 LUT's
// 400 chunks are still found in 3 node reads.
constexpr unsigned kChunkIndexK = 8;
// Largest rank a read accepts; our datasets have rank <= 3.
constexpr int kMaxRank = 8;
// Filter parameters read per filter when listing a dataset's filters (deflate uses 1, shuffle 1).
constexpr size_t kMaxFilterParams = 8;

struct TypeInfo {
  hid_t le, be, mem;
  size_t size;
};

TypeInfo info(Type t) {
  switch (t) {
    case Type::float64: return {H5T_IEEE_F64LE, H5T_IEEE_F64BE, H5T_NATIVE_DOUBLE, 8};
    case Type::float32: return {H5T_IEEE_F32LE, H5T_IEEE_F32BE, H5T_NATIVE_FLOAT, 4};
    case Type::int32: return {H5T_STD_I32LE, H5T_STD_I32BE, H5T_NATIVE_INT32, 4};
    case Type::int64: return {H5T_STD_I64LE, H5T_STD_I64BE, H5T_NATIVE_INT64, 8};
    case Type::uint8: return {H5T_STD_U8LE, H5T_STD_U8BE, H5T_NATIVE_UINT8, 1};
    case Type::int16: return {H5T_STD_I16LE, H5T_STD_I16BE, H5T_NATIVE_INT16, 2};
    case Type::int8: return {H5T_STD_I8LE, H5T_STD_I8BE, H5T_NATIVE_INT8, 1};
  }
  return {H5T_IEEE_F64LE, H5T_IEEE_F64BE, H5T_NATIVE_DOUBLE, 8};
}

bool type_is(hid_t stored, Type t) {
  const TypeInfo ti = info(t);
  return H5Tequal(stored, ti.le) > 0 || H5Tequal(stored, ti.be) > 0;
}

std::string describe_type_bare(hid_t t);

// "a 4-byte signed integer", "an 8-byte float", ...
std::string describe_type(hid_t t) {
  const std::string d = describe_type_bare(t);
  return (d[0] == '8' || d[0] == 'a' || d[0] == 'e' || d[0] == 'o' || d[0] == 'u' ? "an " : "a ") + d;
}

std::string describe_type_bare(hid_t t) {
  const H5T_class_t c = H5Tget_class(t);
  const size_t size = H5Tget_size(t);
  const std::string bytes = std::to_string(size) + "-byte";
  switch (c) {
    case H5T_INTEGER: return bytes + (H5Tget_sign(t) == H5T_SGN_NONE ? " unsigned integer" : " signed integer");
    case H5T_FLOAT: return bytes + " float";
    case H5T_STRING: return H5Tis_variable_str(t) > 0 ? "variable-length string" : bytes + " string";
    case H5T_COMPOUND: return "compound type";
    case H5T_ENUM: return "enum type";
    case H5T_ARRAY: return "array type";
    case H5T_VLEN: return "variable-length type";
    case H5T_OPAQUE: return "opaque type";
    case H5T_REFERENCE: return "reference type";
    case H5T_BITFIELD: return "bitfield type";
    default: return "unknown type";
  }
}

const char* link_kind(H5L_type_t t) {
  switch (t) {
    case H5L_TYPE_HARD: return "a hard link";
    case H5L_TYPE_SOFT: return "a soft link";
    case H5L_TYPE_EXTERNAL: return "an external link";
    default: return "a user-defined link";
  }
}

std::string pattern_text(const ShapePattern& p) {
  if (p.empty()) return "scalar";
  std::string s;
  for (size_t i = 0; i < p.size(); ++i) {
    if (i) s += " x ";
    s += p[i] < 0 ? std::string("*") : std::to_string(p[i]);
  }
  return s;
}

// Product of extents times element size; false on overflow.
bool checked_bytes(const Shape& shape, std::uint64_t elem, std::uint64_t* bytes) {
  std::uint64_t n = elem;
  for (std::uint64_t d : shape) {
    if (d != 0 && n > std::numeric_limits<std::uint64_t>::max() / d) return false;
    n *= d;
  }
  *bytes = n;
  return true;
}

std::uint64_t element_count(const Shape& shape) {
  std::uint64_t n = 1;
  for (auto d : shape) n *= d;
  return n;
}

herr_t close_object(hid_t id) { return H5Oclose(id); }

[[noreturn]] void fail_io(const std::string& file, const std::string& object, const std::string& what) {
  std::string detail = take_error_detail();
  throw IoError(file + ": " + object + ": " + what + (detail.empty() ? "" : " (" + detail + ")"));
}

Handle make_plist(hid_t cls) {
  Handle p(H5Pcreate(cls), H5Pclose);
  if (!p.valid()) throw IoError("HDF5: cannot create a property list (" + take_error_detail() + ")");
  return p;
}

// Writes a scalar attribute of stored type `ftype` from memory of type `mtype`.
void write_attr(hid_t obj, const std::string& file, const std::string& object, const std::string& name,
                hid_t ftype, hid_t mtype, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (!space.valid()) fail_io(file, object, "cannot create dataspace for attribute " + name);
  if (H5Aexists(obj, name.c_str()) > 0 && H5Adelete(obj, name.c_str()) < 0)
    fail_io(file, object, "cannot replace attribute " + name);
  Handle attr(H5Acreate2(obj, name.c_str(), ftype, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) fail_io(file, object, "cannot create attribute " + name);
  if (H5Awrite(attr.get(), mtype, value) < 0) fail_io(file, object, "cannot write attribute " + name);
  if (attr.close() < 0) fail_io(file, object, "cannot close attribute " + name);
}

void write_string_attr(hid_t obj, const std::string& file, const std::string& object, const std::string& name,
                       const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), value.size() + 1) < 0 || H5Tset_strpad(type.get(), H5T_STR_NULLTERM) < 0 ||
      H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    fail_io(file, object, "cannot make the string type of attribute " + name);
  write_attr(obj, file, object, name, type.get(), type.get(), value.c_str());
}

struct LinkList {
  std::vector<std::pair<std::string, H5L_type_t>> links;
  bool too_many = false;
};

herr_t collect_link(hid_t, const char* name, const H5L_info_t* li, void* data) {
  auto* list = static_cast<LinkList*>(data);
  if (list->links.size() >= kMaxGroupLinks) {
    list->too_many = true;
    return 1;  // stop
  }
  list->links.emplace_back(name, li->type);
  return 0;
}

struct ErrorWalk {
  std::string innermost;
};

herr_t walk_error(unsigned, const H5E_error2_t* err, void* data) {
  auto* w = static_cast<ErrorWalk*>(data);
  if (!w->innermost.empty()) return 0;
  if (err->desc && *err->desc) {
    w->innermost = err->desc;
  } else {
    char buf[256] = {0};
    if (H5Eget_msg(err->min_num, nullptr, buf, sizeof buf) > 0) w->innermost = buf;
  }
  return 0;
}

}  // namespace

void leave_library_at_exit() { H5dont_atexit(); }

void init() {
  static const bool once = [] {
    H5open();
    H5PLset_loading_state(0);  // never load filter plugins a file names
    return true;
  }();
  (void)once;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // per thread in thread-safe builds: set on every entry
}

std::string take_error_detail() {
  ErrorWalk w;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk_error, &w);
  H5Eclear2(H5E_DEFAULT);
  std::string d = std::move(w.innermost);
  std::replace(d.begin(), d.end(), '\n', ' ');
  // System-call failures come as "file write failed: time = ..., errno = 27, error message = 'File too
  // large', ..."; keep the operation and the system's message.
  const auto time_at = d.find(": time = ");
  const auto msg_at = d.find("error message = '");
  if (time_at != std::string::npos && msg_at != std::string::npos) {
    const auto start = msg_at + 17;
    const auto end = d.find('\'', start);
    d = d.substr(0, time_at) + ": " + d.substr(start, end == std::string::npos ? std::string::npos : end - start);
  }
  return d;
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    close();
    id_ = o.id_;
    closer_ = o.closer_;
    o.id_ = H5I_INVALID_HID;
  }
  return *this;
}

herr_t Handle::close() {
  herr_t r = 0;
  if (id_ >= 0 && closer_) r = closer_(id_);
  id_ = H5I_INVALID_HID;
  return r;
}

std::string shape_text(const Shape& s) {
  ShapePattern p(s.begin(), s.end());
  return pattern_text(p);
}

const char* type_name(Type t) {
  switch (t) {
    case Type::float64: return "float64";
    case Type::float32: return "float32";
    case Type::int32: return "int32";
    case Type::int64: return "int64";
    case Type::uint8: return "uint8";
    case Type::int16: return "int16";
    case Type::int8: return "int8";
  }
  return "?";
}

std::string Group::child_path(const std::string& name) const { return path_ == "/" ? "/" + name : path_ + "/" + name; }


void Group::fail(const std::string& object, const std::string& what) const {
  H5Eclear2(H5E_DEFAULT);
  throw InputError(printable_text(file_ + ": " + object + ": " + what));
}

// ---------------------------------------------------------------- writing

Group Group::create_group(const std::string& name) {
  init();
  Handle gcpl = make_plist(H5P_GROUP_CREATE);
  H5Pset_obj_track_times(gcpl.get(), 0);  // no timestamps: identical content gives identical bytes
  H5Pset_attr_phase_change(gcpl.get(), kMaxCompactAttributes, kMaxCompactAttributes - 1);
  Handle g(H5Gcreate2(id(), name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail_io(file_, child_path(name), "cannot create group");
  Group child(std::move(g), file_, child_path(name));
  child.compress_ = compress_;
  return child;
}

void Group::set_attr(const std::string& name, const std::string& value) {
  init();
  write_string_attr(id(), file_, path_, name, value);
}
void Group::set_attr(const std::string& name, double value) {
  init();
  write_attr(id(), file_, path_, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}
void Group::set_attr(const std::string& name, std::int32_t value) {
  init();
  write_attr(id(), file_, path_, name, H5T_STD_I32LE, H5T_NATIVE_INT32, &value);
}
void Group::set_attr(const std::string& name, std::int64_t value) {
  init();
  write_attr(id(), file_, path_, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value);
}
void Group::set_attr(const std::string& name, bool value) {
  init();
  const std::uint8_t v = value ? 1 : 0;
  write_attr(id(), file_, path_, name, H5T_STD_U8LE, H5T_NATIVE_UINT8, &v);
}

void Group::write_raw(const std::string& name, Type type, const void* data, const Shape& shape, const std::string& unit,
                      const std::string& description) {
  init();
  const std::string object = child_path(name);
  const TypeInfo ti = info(type);
  std::uint64_t bytes = 0;
  if (!checked_bytes(shape, ti.size, &bytes)) fail_io(file_, object, "shape " + shape_text(shape) + " overflows");
  const int rank = static_cast<int>(shape.size());
  std::vector<hsize_t> dims(shape.begin(), shape.end());
  Handle space(rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims.data(), nullptr), H5Sclose);
  if (!space.valid()) fail_io(file_, object, "cannot create dataspace " + shape_text(shape));

  Handle dcpl = make_plist(H5P_DATASET_CREATE);
  H5Pset_obj_track_times(dcpl.get(), 0);
  H5Pset_attr_phase_change(dcpl.get(), kMaxCompactAttributes, kMaxCompactAttributes - 1);
  if (rank > 0 && bytes > 0) {
    // Chunk = whole trailing extents; leading extents cut so a chunk holds at most kChunkTargetBytes.
    std::vector<hsize_t> chunk = dims;
    for (int i = 0; i < rank; ++i) {
      std::uint64_t rest = ti.size;
      for (int j = i + 1; j < rank; ++j) rest *= chunk[j];
      if (rest * chunk[i] <= kChunkTargetBytes) break;
      chunk[i] = std::max<std::uint64_t>(1, kChunkTargetBytes / rest);
      if (rest <= kChunkTargetBytes) break;
    }
    if (H5Pset_chunk(dcpl.get(), rank, chunk.data()) < 0) fail_io(file_, object, "cannot set chunking");
    if (compress_ && bytes >= kCompressMinBytes) {
      if (H5Pset_shuffle(dcpl.get()) < 0 || H5Pset_deflate(dcpl.get(), kDeflateLevel) < 0)
        fail_io(file_, object, "cannot set compression");
    }
    // Checksum last in the pipeline: it covers the stored (compressed) bytes and is verified first on read.
    if (H5Pset_fletcher32(dcpl.get()) < 0) fail_io(file_, object, "cannot set the Fletcher32 checksum");
  }
  Handle dset(H5Dcreate2(id(), name.c_str(), ti.le, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), H5Dclose);
  if (!dset.valid()) fail_io(file_, object, "cannot create dataset");
  if (bytes > 0 && H5Dwrite(dset.get(), ti.mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail_io(file_, object, "cannot write dataset");
  write_string_attr(dset.get(), file_, object, "unit", unit);
  if (!description.empty()) write_string_attr(dset.get(), file_, object, "description", description);
  if (dset.close() < 0) fail_io(file_, object, "cannot close dataset");
}

void Group::write_matrix(const std::string& name, const Eigen::MatrixXd& m, const std::string& unit,
                         const std::string& description) {
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
  write(name, r.data(), Shape{static_cast<std::uint64_t>(m.rows()), static_cast<std::uint64_t>(m.cols())}, unit,
        description);
}

// ---------------------------------------------------------------- reading

std::vector<std::string> Group::children() const {
  init();
  H5G_info_t gi;
  if (H5Gget_info(id(), &gi) < 0) fail(path_, "cannot list the group (" + take_error_detail() + ")");
  if (gi.nlinks > kMaxGroupLinks)
    fail(path_, "group has " + std::to_string(gi.nlinks) + " links, more than the limit of " + std::to_string(kMaxGroupLinks));
  LinkList list;
  hsize_t idx = 0;
  if (H5Literate(id(), H5_INDEX_NAME, H5_ITER_INC, &idx, collect_link, &list) < 0)
    fail(path_, "cannot list the group (" + take_error_detail() + ")");
  if (list.too_many) fail(path_, "group has more than " + std::to_string(kMaxGroupLinks) + " links");
  std::vector<std::string> names;
  for (auto& [n, t] : list.links) {
    if (t != H5L_TYPE_HARD) fail(child_path(n), std::string("expected a hard link, found ") + link_kind(t));
    names.push_back(n);
  }
  return names;
}

void Group::check_links() const { (void)children(); }

bool Group::has(const std::string& name) const {
  init();
  if (name.empty() || name.find('/') != std::string::npos) fail(child_path(name), "invalid link name");
  const htri_t e = H5Lexists(id(), name.c_str(), H5P_DEFAULT);
  if (e < 0) fail(child_path(name), "cannot look up the link (" + take_error_detail() + ")");
  if (e == 0) return false;
  H5L_info_t li;
  if (H5Lget_info(id(), name.c_str(), &li, H5P_DEFAULT) < 0)
    fail(child_path(name), "cannot read the link (" + take_error_detail() + ")");
  if (li.type != H5L_TYPE_HARD) fail(child_path(name), std::string("expected a hard link, found ") + link_kind(li.type));
  return true;
}

bool Group::is_group(const std::string& name) const {
  if (!has(name)) fail(child_path(name), "missing object");
  Handle o(H5Oopen(id(), name.c_str(), H5P_DEFAULT), close_object);
  if (!o.valid()) fail(child_path(name), "cannot open object (" + take_error_detail() + ")");
  return H5Iget_type(o.get()) == H5I_GROUP;
}

Group Group::open_group(const std::string& name) const {
  const std::string object = child_path(name);
  if (!has(name)) fail(object, "missing group");
  Handle o(H5Oopen(id(), name.c_str(), H5P_DEFAULT), close_object);
  if (!o.valid()) fail(object, "cannot open group (" + take_error_detail() + ")");
  const H5I_type_t t = H5Iget_type(o.get());
  if (t != H5I_GROUP) fail(object, std::string("expected a group, found a ") + (t == H5I_DATASET ? "dataset" : "named datatype"));
  return Group(std::move(o), file_, object);
}

Group Group::attributes_of(const std::string& name) const {
  const std::string object = child_path(name);
  if (!has(name)) fail(object, "missing object");
  Handle o(H5Oopen(id(), name.c_str(), H5P_DEFAULT), close_object);
  if (!o.valid()) fail(object, "cannot open (" + take_error_detail() + ")");
  return Group(std::move(o), file_, object);
}

bool Group::has_attr(const std::string& name) const {
  init();
  const htri_t e = H5Aexists(id(), name.c_str());
  if (e < 0) fail(path_, "cannot look up attribute " + name + " (" + take_error_detail() + ")");
  return e > 0;
}

namespace {

// Opens a scalar attribute and returns it with its stored type.
Handle open_scalar_attr(const Group& g, const std::string& name, Handle* type) {
  const std::string where = g.path() + " attribute " + name;
  if (!g.has_attr(name)) g.fail(g.path(), "missing attribute " + name);
  Handle a(H5Aopen(g.id(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.valid()) g.fail(where, "cannot open (" + take_error_detail() + ")");
  Handle space(H5Aget_space(a.get()), H5Sclose);
  if (!space.valid() || H5Sget_simple_extent_type(space.get()) != H5S_SCALAR)
    g.fail(g.path(), "attribute " + name + ": expected a scalar, found an array or empty dataspace");
  *type = Handle(H5Aget_type(a.get()), H5Tclose);
  if (!type->valid()) g.fail(g.path(), "attribute " + name + ": cannot read its type");
  return a;
}

}  // namespace

std::string Group::attr_string(const std::string& name) const {
  Handle type;
  Handle a = open_scalar_attr(*this, name, &type);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    fail(path_, "attribute " + name + ": expected a fixed-length string, found " + describe_type(type.get()));
  const size_t size = H5Tget_size(type.get());
  if (size == 0 || size > kMaxStringBytes)
    fail(path_, "attribute " + name + ": expected a string of at most " + std::to_string(kMaxStringBytes) + " bytes, found " +
                    std::to_string(size));
  std::string buf(size, '\0');
  if (H5Aread(a.get(), type.get(), buf.data()) < 0) fail(path_, "attribute " + name + ": cannot read (" + take_error_detail() + ")");
  const auto nul = buf.find('\0');
  if (nul != std::string::npos) buf.resize(nul);
  return buf;
}

double Group::attr_double(const std::string& name) const {
  Handle type;
  Handle a = open_scalar_attr(*this, name, &type);
  if (!type_is(type.get(), Type::float64))
    fail(path_, "attribute " + name + ": expected float64, found " + describe_type(type.get()));
  double v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v) < 0) fail(path_, "attribute " + name + ": cannot read (" + take_error_detail() + ")");
  return v;
}

std::int64_t Group::attr_int(const std::string& name, std::int64_t lo, std::int64_t hi) const {
  Handle type;
  Handle a = open_scalar_attr(*this, name, &type);
  if (!type_is(type.get(), Type::int32) && !type_is(type.get(), Type::int64))
    fail(path_, "attribute " + name + ": expected int32, found " + describe_type(type.get()));
  std::int64_t v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_INT64, &v) < 0) fail(path_, "attribute " + name + ": cannot read (" + take_error_detail() + ")");
  if (v < lo || v > hi)
    fail(path_, "attribute " + name + ": expected a value in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], found " +
                    std::to_string(v));
  return v;
}

bool Group::attr_bool(const std::string& name) const {
  Handle type;
  Handle a = open_scalar_attr(*this, name, &type);
  if (!type_is(type.get(), Type::uint8)) fail(path_, "attribute " + name + ": expected uint8 0/1, found " + describe_type(type.get()));
  std::uint8_t v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_UINT8, &v) < 0) fail(path_, "attribute " + name + ": cannot read (" + take_error_detail() + ")");
  if (v > 1) fail(path_, "attribute " + name + ": expected 0 or 1, found " + std::to_string(v));
  return v == 1;
}

Handle Group::open_dataset_checked(const std::string& name, const ReadLimits& limits, Shape* shape, Handle* type) const {
  const std::string object = child_path(name);
  if (!has(name)) fail(object, "missing dataset");
  Handle d(H5Oopen(id(), name.c_str(), H5P_DEFAULT), close_object);
  if (!d.valid()) fail(object, "cannot open dataset (" + take_error_detail() + ")");
  if (H5Iget_type(d.get()) != H5I_DATASET) fail(object, "expected a dataset, found a group");

  Handle dcpl(H5Dget_create_plist(d.get()), H5Pclose);
  if (!dcpl.valid()) fail(object, "cannot read the storage properties (" + take_error_detail() + ")");
  const H5D_layout_t layout = H5Pget_layout(dcpl.get());
  if (layout == H5D_VIRTUAL) fail(object, "expected data stored in this file, found a virtual dataset");
  if (layout != H5D_CONTIGUOUS && layout != H5D_CHUNKED && layout != H5D_COMPACT)
    fail(object, "unknown storage layout");
  const int external = H5Pget_external_count(dcpl.get());
  if (external != 0) fail(object, "expected data stored in this file, found external storage in " + std::to_string(external) + " file(s)");
  const int nfilters = H5Pget_nfilters(dcpl.get());
  if (nfilters < 0) fail(object, "cannot read the filter pipeline");
  for (int i = 0; i < nfilters; ++i) {
    unsigned flags = 0, cd[kMaxFilterParams];
    size_t ncd = kMaxFilterParams;
    char fname[64] = {0};
    unsigned config = 0;
    const H5Z_filter_t f = H5Pget_filter2(dcpl.get(), static_cast<unsigned>(i), &flags, &ncd, cd, sizeof fname, fname, &config);
    if (f != H5Z_FILTER_DEFLATE && f != H5Z_FILTER_SHUFFLE && f != H5Z_FILTER_FLETCHER32)
      fail(object, "expected only deflate, shuffle and Fletcher32 filters, found filter id " + std::to_string(f));
  }

  *type = Handle(H5Dget_type(d.get()), H5Tclose);
  if (!type->valid()) fail(object, "cannot read the element type (" + take_error_detail() + ")");
  Handle space(H5Dget_space(d.get()), H5Sclose);
  if (!space.valid()) fail(object, "cannot read the dataspace (" + take_error_detail() + ")");
  const H5S_class_t sc = H5Sget_simple_extent_type(space.get());
  if (sc != H5S_SIMPLE && sc != H5S_SCALAR) fail(object, "expected an array, found an empty (null) dataspace");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > kMaxRank) fail(object, "expected rank at most " + std::to_string(kMaxRank) + ", found " + std::to_string(rank));
  std::vector<hsize_t> dims(static_cast<size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0) fail(object, "cannot read the extents");
  shape->assign(dims.begin(), dims.end());
  std::uint64_t bytes = 0;
  const size_t elem = H5Tget_size(type->get());
  if (!checked_bytes(*shape, std::max<size_t>(elem, 1), &bytes) || bytes > limits.max_dataset_bytes)
    fail(object, "declares shape " + shape_text(*shape) + " (" + (bytes ? std::to_string(bytes) : std::string("overflowing")) +
                     " bytes), expected at most the limit of " + std::to_string(limits.max_dataset_bytes) + " bytes");
  return d;
}

Type Group::dataset_type(const std::string& name, const ReadLimits& limits) const {
  init();
  Shape shape;
  Handle type;
  Handle d = open_dataset_checked(name, limits, &shape, &type);
  for (Type t : {Type::float64, Type::float32, Type::int32, Type::int64, Type::uint8, Type::int16, Type::int8})
    if (type_is(type.get(), t)) return t;
  fail(child_path(name), "expected float64, float32, int32, int64, uint8, int16 or int8, found " + describe_type(type.get()));
}

Shape Group::dataset_shape(const std::string& name, const ReadLimits& limits) const {
  init();
  Shape shape;
  Handle type;
  Handle d = open_dataset_checked(name, limits, &shape, &type);
  return shape;
}

namespace {

// The running sum of a ReadScope on this thread (icobrdf/io/h5_file.hpp).
struct ScopeBytes {
  bool active = false;
  std::uint64_t bytes = 0;
};
thread_local ScopeBytes t_scope;

// Adds a read of `bytes` (in memory) to this thread's scope and refuses it when the sum exceeds the budget.
void hold_to_budget(const std::string& file, const std::string& object, const Shape& shape, std::uint64_t bytes) {
  const std::uint64_t sum = t_scope.active ? t_scope.bytes + bytes : bytes;
  if (t_scope.active) t_scope.bytes = sum;
  if (sum < kBudgetCheckBytes) return;
  require_memory(static_cast<double>(sum), printable_text(file + ": " + object) + " (declared shape " + shape_text(shape) + ")" +
                                              (sum > bytes ? " with the datasets of its object read before it" : ""),
                 "the file declares more than this machine holds");
}

}  // namespace

ReadScope::ReadScope() : outer_active_(t_scope.active), outer_bytes_(t_scope.bytes) { t_scope = ScopeBytes{true, 0}; }
ReadScope::~ReadScope() { t_scope = ScopeBytes{outer_active_, outer_bytes_}; }

void Group::read_raw(const std::string& name, Type type, bool allow_float32, const ShapePattern& pattern,
                     const ReadLimits& limits, Shape* shape, void* (*alloc)(void*, std::uint64_t), void* vec) const {
  // `type` is the memory type; the stored type must equal it, except that with allow_float32 a float32
  // dataset is read into float64.
  init();
  const std::string object = child_path(name);
  Handle stored;
  Handle d = open_dataset_checked(name, limits, shape, &stored);
  const bool f32 = allow_float32 && type == Type::float64;
  const bool ok = type_is(stored.get(), type) || (f32 && type_is(stored.get(), Type::float32));
  if (!ok)
    fail(object, std::string("expected ") + (f32 ? "float64 or float32" : type_name(type)) + ", found " +
                     describe_type(stored.get()));
  bool shape_ok = shape->size() == pattern.size();
  for (size_t i = 0; shape_ok && i < pattern.size(); ++i)
    if (pattern[i] >= 0 && (*shape)[i] != static_cast<std::uint64_t>(pattern[i])) shape_ok = false;
  if (!shape_ok) fail(object, "expected shape " + pattern_text(pattern) + ", found " + shape_text(*shape));
  std::uint64_t mem_bytes = 0;
  if (!checked_bytes(*shape, info(type).size, &mem_bytes) || mem_bytes > limits.max_dataset_bytes)
    fail(object, "needs " + std::to_string(mem_bytes) + " bytes in memory, expected at most the limit of " +
                     std::to_string(limits.max_dataset_bytes));
  const std::uint64_t n = element_count(*shape);
  hold_to_budget(file_, object, *shape, mem_bytes + (type == Type::float64 ? 0 : n * sizeof(double)));
  void* buf = alloc(vec, n);
  if (n == 0) return;
  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  if (!dxpl.valid() || H5Pset_edc_check(dxpl.get(), H5Z_ENABLE_EDC) < 0) fail(object, "cannot set up the read");
  if (H5Dread(d.get(), info(type).mem, H5S_ALL, H5S_ALL, dxpl.get(), buf) < 0)
    fail(object, "cannot read the data (" + take_error_detail() + ")");
}

Array<double> Group::read_real(const std::string& name, const ShapePattern& pattern, const ReadLimits& limits) const {
  Array<double> out;
  read_raw(name, Type::float64, true, pattern, limits, &out.shape,
           [](void* v, std::uint64_t n) -> void* {
             auto* vec = static_cast<std::vector<double>*>(v);
             vec->resize(n);
             return vec->data();
           },
           &out.data);
  return out;
}

// ---------------------------------------------------------------- files

WriteFile WriteFile::create(const std::string& path, const std::string& display_path) {
  init();
  Handle fapl = make_plist(H5P_FILE_ACCESS);
  if (H5Pset_fapl_sec2(fapl.get()) < 0 || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0 ||
      H5Pset_file_locking(fapl.get(), 1, 1) < 0)
    fail_io(display_path, "/", "cannot set file access properties");
  Handle fcpl = make_plist(H5P_FILE_CREATE);
  if (!fcpl.valid() || H5Pset_istore_k(fcpl.get(), kChunkIndexK) < 0) fail_io(display_path, "/", "cannot set file creation properties");
  Handle f(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), H5Fclose);
  if (!f.valid()) fail_io(display_path, "/", "cannot create HDF5 file " + path);
  return WriteFile(std::move(f), display_path);
}

// Bytes by which the core driver grows an in-memory file.
constexpr std::size_t kCoreIncrement = std::size_t{1} << 20;

WriteFile WriteFile::create_in_memory(const std::string& display_path) {
  init();
  Handle fapl = make_plist(H5P_FILE_ACCESS);
  if (H5Pset_fapl_core(fapl.get(), kCoreIncrement, 0) < 0 || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0)
    fail_io(display_path, "/", "cannot set in-memory file access properties");
  Handle f(H5Fcreate(display_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose);
  if (!f.valid()) fail_io(display_path, "/", "cannot create an in-memory HDF5 file");
  WriteFile w(std::move(f), display_path);
  w.compress_ = false;
  return w;
}

std::string WriteFile::finish_image() {
  init();
  if (H5Fflush(f_.get(), H5F_SCOPE_GLOBAL) < 0) fail_io(path_, "/", "cannot flush the file");
  {
    Group r = root();
    r.set_attr("complete", true);
  }
  if (H5Fflush(f_.get(), H5F_SCOPE_GLOBAL) < 0) fail_io(path_, "/", "cannot flush the file");
  const ssize_t size = H5Fget_file_image(f_.get(), nullptr, 0);
  if (size < 0) fail_io(path_, "/", "cannot take the file's image");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (H5Fget_file_image(f_.get(), bytes.data(), bytes.size()) != size) fail_io(path_, "/", "cannot take the file's image");
  if (f_.close() < 0) fail_io(path_, "/", "cannot close the file");
  return bytes;
}

Group WriteFile::root() {
  Handle g(H5Gopen2(f_.get(), "/", H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail_io(path_, "/", "cannot open the root group");
  Group r(std::move(g), path_, "/");
  r.compress_ = compress_;
  return r;
}

void WriteFile::finish() {
  init();
  if (H5Fflush(f_.get(), H5F_SCOPE_GLOBAL) < 0) fail_io(path_, "/", "cannot flush the file");
  {
    Group r = root();
    r.set_attr("complete", true);
  }
  if (H5Fflush(f_.get(), H5F_SCOPE_GLOBAL) < 0) fail_io(path_, "/", "cannot flush the file");
  if (f_.close() < 0) fail_io(path_, "/", "cannot close the file");
}

ReadFile ReadFile::open(const std::string& path) {
  init();
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw InputError(path + ": /: expected a regular file, found " + (S_ISDIR(st.st_mode) ? "a directory" : "a special file"));
  {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
    ::close(fd);
  }
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.valid() || H5Pset_fapl_sec2(fapl.get()) < 0 || H5Pset_file_locking(fapl.get(), 1, 1) < 0)
    throw IoError(path + ": cannot set file access properties (" + take_error_detail() + ")");
  const htri_t is = H5Fis_hdf5(path.c_str());
  if (is <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw InputError(path + ": /: expected an HDF5 file, found no HDF5 signature (" + std::to_string(st.st_size) + " bytes)");
  }
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose);
  if (!f.valid()) throw InputError(path + ": /: cannot open as HDF5 (" + take_error_detail() + ")");
  return ReadFile(std::move(f), path);
}

ReadFile ReadFile::open_image(const std::string& bytes, const std::string& display_path) {
  init();
  static const char kSignature[] = "\x89HDF\r\n\x1a\n";
  if (bytes.size() < 8 || bytes.compare(0, 8, kSignature, 8) != 0)
    throw InputError(display_path + ": /: expected an HDF5 file, found no HDF5 signature (" + std::to_string(bytes.size()) + " bytes)");
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), kCoreIncrement, 0) < 0 ||
      H5Pset_file_image(fapl.get(), const_cast<char*>(bytes.data()), bytes.size()) < 0)
    throw IoError(display_path + ": cannot set in-memory file access properties (" + take_error_detail() + ")");
  Handle f(H5Fopen(display_path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose);
  if (!f.valid()) throw InputError(display_path + ": /: cannot open as HDF5 (" + take_error_detail() + ")");
  return ReadFile(std::move(f), display_path);
}

Group ReadFile::root() const {
  Handle g(H5Gopen2(f_.get(), "/", H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw InputError(path_ + ": /: cannot open the root group (" + take_error_detail() + ")");
  return Group(std::move(g), path_, "/");
}

}  // namespace icobrdf::h5
