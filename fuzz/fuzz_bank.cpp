// libFuzzer target: the bank validator (icobrdf/io/bank_file.hpp read_bank, read_bank_material, bank_material_names).
//
// Banks are trusted input beyond the validation (docs/reliability.md): HDF5 itself parses the file
// structure, and HDF5 1.10 can crash or hang on crafted bytes. So this target fuzzes what icobrdf owns, the
// validation of well-formed HDF5 files: it starts from a complete valid bank (grid, basis arrays, an
// isotropic material with IBSSS and a float64 LUT, a 3-channel material with a float32 LUT, choice
// figures and labels) and applies up to kMaxEdits edits decoded from the input through the HDF5 API:
//   delete a link; replace an object by a dataset of another type (float / integer / string, either byte
//   order), rank, shape (including absurd declared extents, never allocated) and filters; set or delete an
//   attribute (any of the names the format uses, any type and value); create a group; add a soft, external
//   or hard link (cycles included); overwrite bytes of a dataset's values (NaN, Inf, out-of-range indices);
//   copy an object elsewhere; and flip bytes inside a stored chunk after closing the file (checksum and
//   deflate paths). Every read must then return or throw InputError / IoError (fuzz/fuzz_support.hpp).
// Reads use a 64 MiB dataset limit, so that a declared extent the reader rightly accepts (the default limit
// is 4 GiB) does not exhaust the fuzzer's memory.
#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "fuzz/fuzz_support.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/h5_file.hpp"
#include "icobrdf/mesh/tessellation.hpp"

using namespace icobrdf;

namespace {

constexpr int kMaxEdits = 6;
// Largest dataset the fuzzed reads accept (see the header comment).
constexpr std::uint64_t kReadLimitBytes = std::uint64_t{64} << 20;
// Largest number of elements a replaced dataset is written with; larger declared extents stay unwritten.
constexpr hsize_t kMaxWrittenElements = 4096;

std::vector<unsigned char> g_valid;  // bytes of the valid bank

Eigen::MatrixXd patterned(Eigen::Index rows, Eigen::Index cols, double seed) {
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) m(i, j) = 0.5 + 0.25 * std::sin(seed + 0.7 * i + 0.31 * j);
  return m;
}

BankContents valid_bank() {
  BankContents b;
  b.grid = build_equal_area_grid(1);
  b.created = "2026-01-01T00:00:00Z";
  const int cells = b.grid->cells();
  MaterialRecord iso;
  iso.name = "iso";
  iso.spectrum.order = 2;
  iso.spectrum.isotropic = true;
  iso.spectrum.source = "model:lambert:albedo=0.5";
  iso.spectrum.level = 1;
  iso.spectrum.grid_kind = "equal-area";
  const int k = isotropic_mode_count(2);
  Eigen::VectorXd a(k);
  for (int i = 0; i < k; ++i) a[i] = 0.3 / (1 + i);
  iso.spectrum.channels = {coefficients_from_ibsss(2, a)};
  iso.ibsss = a.transpose();
  const auto modes = isotropic_modes(2);
  iso.ibsss_indices.resize(k, 3);
  for (int i = 0; i < k; ++i) iso.ibsss_indices.row(i) << modes[i].n, modes[i].m, modes[i].l;
  iso.lut = {patterned(cells, cells, 1.0)};
  iso.figures = {{"target", 0.01}, {"seconds", 0.5}};
  iso.labels = {{"key", "0123456789abcdef"}};
  MaterialRecord rgb;
  rgb.name = "rgb";
  rgb.spectrum.order = 1;
  rgb.spectrum.source = "model:test";
  rgb.spectrum.level = 2;
  rgb.spectrum.grid_kind = "test-cells";
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd s = patterned(rgb.spectrum.modes(), rgb.spectrum.modes(), c);
    rgb.spectrum.channels.push_back(s + s.transpose());
    rgb.lut.push_back(patterned(40, 40, 2.0 + c));
  }
  rgb.lut_float32 = true;
  b.materials = {iso, rgb};
  b.basis.push_back(BasisArray::matrix("2/B", patterned(cells, 6, 3.0), "1/sqrt(sr)", "cells x modes"));
  BasisArray idx;
  idx.path = "2/indices";
  idx.shape = {6, 2};
  idx.indices = {0, 0, 1, -1, 1, 1, 2, -2, 2, 0, 2, 2};
  idx.unit = "index";
  b.basis.push_back(idx);
  return b;
}

herr_t collect_link(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->push_back(std::string("/") + name);
  return 0;
}

const char* const kNames[] = {"grid",  "basis", "materials", "iso",    "rgb",           "C",      "lut",
                              "ibsss", "ibsss_indices", "choice", "2",  "B",        "indices", "directions",
                              "solid_angles", "faces", "x", "a.b", "", "neighbours"};
const char* const kAttrNames[] = {"format",      "format_version", "complete",   "created",   "creator",    "conventions",
                                  "axis_order",  "order",          "modes",      "channels",  "isotropic",  "cosine",
                                  "source",      "filter",         "level",      "grid_kind", "gram_error", "max_albedo",
                                  "reciprocity_violation", "anisotropy_fraction", "unit", "description", "figures",
                                  "labels",      "lut_max_abs_rounding_error", "kind", "cells", "cubature_degree",
                                  "target",      "seconds",        "key"};
const char* const kStrings[] = {"icobrdf-bank", "1.0", "2.0", "0.1", "1.", ".1", "99999999999999.1", "1.99999999999999",
                                "equal-area", "test-cells", "1/sr", "target,seconds", "key", "target,,seconds",
                                "figures", "a,b,c", "none", ""};

struct Editor {
  FuzzedDataProvider& in;
  hid_t file;
  std::vector<std::string> paths;  // every link, "/a/b"

  std::string pick_path() {
    if (paths.empty() || in.ConsumeBool()) return "/";
    return paths[in.ConsumeIntegralInRange<size_t>(0, paths.size() - 1)];
  }
  std::string pick_name() {
    if (in.ConsumeBool()) return in.PickValueInArray(kNames);
    return in.ConsumeRandomLengthString(16);
  }
  std::string new_path() {
    const std::string parent = pick_path();
    return (parent == "/" ? "" : parent) + "/" + pick_name();
  }
  std::string pick_string() { return in.ConsumeBool() ? std::string(in.PickValueInArray(kStrings)) : in.ConsumeRandomLengthString(40); }

  hid_t pick_type() {
    switch (in.ConsumeIntegralInRange(0, 9)) {
      case 0: return H5Tcopy(H5T_IEEE_F64LE);
      case 1: return H5Tcopy(H5T_IEEE_F32LE);
      case 2: return H5Tcopy(H5T_STD_I32LE);
      case 3: return H5Tcopy(H5T_STD_I64LE);
      case 4: return H5Tcopy(H5T_STD_U8LE);
      case 5: return H5Tcopy(H5T_IEEE_F64BE);
      case 6: return H5Tcopy(H5T_STD_I32BE);
      case 7: return H5Tcopy(H5T_STD_I8LE);
      case 8: {
        const hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, in.ConsumeIntegralInRange<size_t>(1, 64));
        return t;
      }
      default: {
        const hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, H5T_VARIABLE);
        return t;
      }
    }
  }

  // Bytes for n elements of `type` (variable-length strings: pointers to fuzzed text).
  std::vector<unsigned char> values(hid_t type, size_t n, std::vector<std::string>* texts) {
    const size_t size = H5Tget_size(type);
    std::vector<unsigned char> buf(n * size);
    if (H5Tis_variable_str(type) > 0) {
      texts->resize(n);
      for (size_t i = 0; i < n; ++i) {
        (*texts)[i] = pick_string();
        const char* p = (*texts)[i].c_str();
        std::memcpy(buf.data() + i * size, &p, sizeof p);
      }
      return buf;
    }
    if (H5Tget_class(type) == H5T_STRING && n > 0) {
      const std::string s = pick_string();
      std::memcpy(buf.data(), s.data(), std::min(s.size(), size));
      return buf;
    }
    const bool special = H5Tget_class(type) == H5T_FLOAT && H5Tget_size(type) == 8 && in.ConsumeBool();
    for (size_t i = 0; i < n; ++i) {
      if (special) {
        const double v = in.PickValueInArray({0.0, -0.0, 1.0, -1.0, 2.0, 1e300, std::numeric_limits<double>::quiet_NaN(),
                                              std::numeric_limits<double>::infinity(), 1e-310, 1000.0, 3.0});
        std::memcpy(buf.data() + i * size, &v, 8);  // LE types: the machine order; BE types then read swapped
      } else {
        const auto bytes = in.ConsumeBytes<unsigned char>(size);
        if (!bytes.empty()) std::memcpy(buf.data() + i * size, bytes.data(), bytes.size());
      }
    }
    return buf;
  }

  void replace_by_dataset() {
    const std::string path = in.ConsumeBool() ? pick_path() : new_path();
    if (path == "/") return;
    H5Ldelete(file, path.c_str(), H5P_DEFAULT);
    const int rank = in.ConsumeIntegralInRange(0, 4);
    std::vector<hsize_t> dims(static_cast<size_t>(rank)), maxdims(static_cast<size_t>(rank));
    bool huge = false;
    for (int r = 0; r < rank; ++r) {
      const int pick = in.ConsumeIntegralInRange(0, 9);
      dims[r] = pick < 8 ? static_cast<hsize_t>(in.PickValueInArray({0, 1, 2, 3, 6, 8, 40, 45})) : hsize_t{1} << in.ConsumeIntegralInRange(20, 62);
      huge = huge || pick >= 8;
      maxdims[r] = H5S_UNLIMITED;
    }
    const hid_t type = pick_type();
    const hid_t space = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims.data(), maxdims.data());
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_obj_track_times(dcpl, 0);
    const bool chunked = rank > 0 && (huge || in.ConsumeBool());
    if (chunked) {
      std::vector<hsize_t> chunk(static_cast<size_t>(rank));
      for (int r = 0; r < rank; ++r) chunk[r] = std::max<hsize_t>(1, std::min<hsize_t>(dims[r], 8));
      H5Pset_chunk(dcpl, rank, chunk.data());
      switch (in.ConsumeIntegralInRange(0, 4)) {
        case 0: H5Pset_fletcher32(dcpl); break;
        case 1: H5Pset_shuffle(dcpl); H5Pset_deflate(dcpl, 4); H5Pset_fletcher32(dcpl); break;
        case 2:  // a filter the reader does not accept; HDF5 1.10's own n-bit writer dereferences a null
                 // pointer for variable-length strings, so those get none (a crash of the editing, not of
                 // the reader under test)
          if (H5Tis_variable_str(type) <= 0) H5Pset_nbit(dcpl);
          break;
        case 3: H5Pset_deflate(dcpl, 1); break;
        default: break;
      }
    }
    if (!chunked && rank > 0) {
      H5Sclose(space);
      const hid_t fixed = H5Screate_simple(rank, dims.data(), nullptr);
      const hid_t d = H5Dcreate2(file, path.c_str(), type, fixed, H5P_DEFAULT, dcpl, H5P_DEFAULT);
      write_all(d, type, fixed);
      if (d >= 0) H5Dclose(d);
      H5Sclose(fixed);
    } else {
      const hid_t d = H5Dcreate2(file, path.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
      if (!huge) write_all(d, type, space);
      if (d >= 0) H5Dclose(d);
      H5Sclose(space);
    }
    H5Pclose(dcpl);
    H5Tclose(type);
  }

  void write_all(hid_t d, hid_t type, hid_t space) {
    if (d < 0) return;
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    if (n <= 0 || static_cast<hsize_t>(n) > kMaxWrittenElements) return;
    std::vector<std::string> texts;
    const auto buf = values(type, static_cast<size_t>(n), &texts);
    H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
  }

  void set_attribute() {
    const std::string path = pick_path();
    const std::string name = in.ConsumeBool() ? std::string(in.PickValueInArray(kAttrNames)) : in.ConsumeRandomLengthString(12);
    if (name.empty()) return;
    const hid_t obj = H5Oopen(file, path.c_str(), H5P_DEFAULT);
    if (obj < 0) return;
    if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
    const hid_t type = pick_type();
    hid_t space;
    size_t n = 1;
    switch (in.ConsumeIntegralInRange(0, 5)) {
      case 0: space = H5Screate(H5S_NULL); n = 0; break;
      case 1: {
        const hsize_t dims[1] = {n = in.ConsumeIntegralInRange<size_t>(0, 3)};
        space = H5Screate_simple(1, dims, nullptr);
        break;
      }
      default: space = H5Screate(H5S_SCALAR); break;
    }
    const hid_t a = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
      std::vector<std::string> texts;
      const auto buf = values(type, n, &texts);
      if (n > 0) H5Awrite(a, type, buf.data());
      H5Aclose(a);
    }
    H5Sclose(space);
    H5Tclose(type);
    H5Oclose(obj);
  }

  void delete_attribute() {
    const std::string path = pick_path();
    const hid_t obj = H5Oopen(file, path.c_str(), H5P_DEFAULT);
    if (obj < 0) return;
    H5Adelete(obj, in.PickValueInArray(kAttrNames));
    H5Oclose(obj);
  }

  void add_link() {
    const std::string at = in.ConsumeBool() ? pick_path() : new_path();
    if (at == "/") return;
    if (in.ConsumeBool()) H5Ldelete(file, at.c_str(), H5P_DEFAULT);
    const std::string target = pick_path();
    switch (in.ConsumeIntegralInRange(0, 3)) {
      case 0: H5Lcreate_soft(target.c_str(), file, at.c_str(), H5P_DEFAULT, H5P_DEFAULT); break;
      case 1: H5Lcreate_external("absent-or-other.h5", target.c_str(), file, at.c_str(), H5P_DEFAULT, H5P_DEFAULT); break;
      default: H5Lcreate_hard(file, target.c_str(), file, at.c_str(), H5P_DEFAULT, H5P_DEFAULT); break;
    }
  }

  void overwrite_values() {
    const hid_t d = H5Dopen2(file, pick_path().c_str(), H5P_DEFAULT);
    if (d < 0) return;
    const hid_t type = H5Dget_type(d), space = H5Dget_space(d);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    if (n > 0 && static_cast<hsize_t>(n) <= (hsize_t{1} << 16) && H5Tis_variable_str(type) <= 0) {
      const size_t size = H5Tget_size(type);
      std::vector<unsigned char> buf(static_cast<size_t>(n) * size);
      if (H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) >= 0) {
        const int edits = in.ConsumeIntegralInRange(1, 4);
        for (int e = 0; e < edits; ++e) {
          const size_t at = in.ConsumeIntegralInRange<size_t>(0, static_cast<size_t>(n) - 1);
          std::vector<std::string> texts;
          const auto v = values(type, 1, &texts);
          std::memcpy(buf.data() + at * size, v.data(), size);
        }
        H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
      }
    }
    H5Sclose(space);
    H5Tclose(type);
    H5Dclose(d);
  }

  // Byte ranges of the chunks of one dataset, for flipping after the file is closed.
  void note_chunks(std::vector<std::pair<haddr_t, hsize_t>>* chunks) {
    const hid_t d = H5Dopen2(file, pick_path().c_str(), H5P_DEFAULT);
    if (d < 0) return;
    const hid_t space = H5Dget_space(d);
    hsize_t count = 0;
    if (H5Dget_num_chunks(d, space, &count) >= 0)
      for (hsize_t i = 0; i < count && i < 16; ++i) {
        hsize_t offset[H5S_MAX_RANK];
        unsigned mask = 0;
        haddr_t addr = 0;
        hsize_t size = 0;
        if (H5Dget_chunk_info(d, space, i, offset, &mask, &addr, &size) >= 0 && addr != HADDR_UNDEF && size > 0)
          chunks->emplace_back(addr, size);
      }
    H5Sclose(space);
    H5Dclose(d);
  }
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  h5::init();
  const fuzz::InputFile seed("bank-seed", ".h5");
  write_bank(seed.path(), valid_bank());
  std::ifstream in(seed.path(), std::ios::binary);
  g_valid.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (g_valid.empty()) fuzz::finding("could not write the valid bank");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  static const fuzz::InputFile file("bank", ".h5");
  FuzzedDataProvider in(data, size);
  file.write(g_valid.data(), g_valid.size());
  std::vector<std::pair<haddr_t, hsize_t>> chunks;
  const hid_t f = H5Fopen(file.path().c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) fuzz::finding("cannot reopen the valid bank");
  {
    Editor e{in, f, {}};
    H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, collect_link, &e.paths);
    const int edits = in.ConsumeIntegralInRange(0, kMaxEdits);
    for (int k = 0; k < edits && in.remaining_bytes() > 0; ++k) {
      switch (in.ConsumeIntegralInRange(0, 8)) {
        case 0: {
          const std::string p = e.pick_path();
          if (p != "/") H5Ldelete(f, p.c_str(), H5P_DEFAULT);
          break;
        }
        case 1: e.replace_by_dataset(); break;
        case 2: e.set_attribute(); break;
        case 3: e.delete_attribute(); break;
        case 4: {
          const hid_t g = H5Gcreate2(f, e.new_path().c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
          if (g >= 0) H5Gclose(g);
          break;
        }
        case 5: e.add_link(); break;
        case 6: e.overwrite_values(); break;
        case 7: H5Ocopy(f, e.pick_path().c_str(), f, e.new_path().c_str(), H5P_DEFAULT, H5P_DEFAULT); break;
        default: e.note_chunks(&chunks); break;
      }
    }
  }
  h5::take_error_detail();  // edits that HDF5 refused leave messages on its stack
  if (H5Fclose(f) < 0) fuzz::finding("cannot close the edited bank");
  if (!chunks.empty()) {
    std::ifstream src(file.path(), std::ios::binary);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(src)), std::istreambuf_iterator<char>());
    for (const auto& [addr, len] : chunks) {
      const size_t at = static_cast<size_t>(addr + in.ConsumeIntegralInRange<hsize_t>(0, len - 1));
      if (at < bytes.size()) bytes[at] ^= std::max<std::uint8_t>(1, in.ConsumeIntegral<std::uint8_t>());
    }
    file.write(bytes.data(), bytes.size());
  }
  ReadOptions o;
  o.max_dataset_bytes = kReadLimitBytes;
  o.read_luts = in.ConsumeBool();
  fuzz::expect_input_errors_only([&] { read_bank(file.path(), o); });
  fuzz::expect_input_errors_only([&] { read_bank_material(file.path(), "", o); });
  fuzz::expect_input_errors_only([&] { read_bank_material(file.path(), "rgb", o); });
  fuzz::expect_input_errors_only([&] { bank_material_names(file.path()); });
  return 0;
}
