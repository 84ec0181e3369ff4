// Reading corrupted or hostile banks: every case must end in a one-line InputError (IoError for a missing
// file) naming the file and the object, print nothing to stderr, and neither crash nor hang. Each read runs
// in a forked child with a timeout, since HDF5 itself parses the file structure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ChildResult;
using icobrdf::test::ScratchDir;

// A reader that takes longer than this on a small file is treated as hung.
constexpr double kChildTimeoutSeconds = 20.0;
// Cells of the "test-cells" LUT of material "big": 3 x 40 x 40 float64 = 38400 bytes, so it is chunked,
// shuffled, deflated and checksummed.
constexpr int kBigCells = 40;

// grid (synthetic, 8 cells) + material "m" (order 2, 3 channels, 8 x 8 float64 LUT on that grid)
// + material "big" (order 1, 1 channel, 40 x 40 LUT of a grid kind the bank does not hold).
void write_valid_bank(const std::string& path) {
  icobrdf::BankContents b;
  b.grid = icobrdf::test::synthetic_grid();
  icobrdf::MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 3);
  for (int c = 0; c < 3; ++c) m.lut.push_back(Eigen::MatrixXd::Constant(8, 8, 0.3 + c));
  icobrdf::MaterialRecord big;
  big.name = "big";
  big.spectrum = icobrdf::test::synthetic_spectrum(1, 1);
  big.spectrum.grid_kind = "test-cells";
  Eigen::MatrixXd f(kBigCells, kBigCells);
  for (int i = 0; i < kBigCells; ++i)
    for (int r = 0; r < kBigCells; ++r) f(i, r) = std::cos(0.1 * i) * std::exp(-0.05 * r) + 1.0 / (1 + i + r);
  big.lut = {f};
  b.materials = {m, big};
  icobrdf::write_bank(path, b);
}

void mutate(const std::string& path, const std::function<void(hid_t)>& f) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  f(file);
  ASSERT_GE(H5Fclose(file), 0);
}

void set_string_attr(hid_t obj, const char* name, const std::string& value) {
  if (H5Aexists(obj, name) > 0) H5Adelete(obj, name);
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, value.size() + 1);
  const hid_t s = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(obj, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, t, value.c_str());
  H5Aclose(a);
  H5Sclose(s);
  H5Tclose(t);
}

// Replaces dataset `where` by one of `type` and `dims`, written from `data` when non-null.
void replace_dataset(hid_t file, const char* where, hid_t type, std::vector<hsize_t> dims, const void* data,
                     hid_t dcpl = H5P_DEFAULT) {
  H5Ldelete(file, where, H5P_DEFAULT);
  const hid_t s = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t d = H5Dcreate2(file, where, type, s, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  if (data) H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Dclose(d);
  H5Sclose(s);
}

// Overwrites one element (flat index) of a float64 dataset with `value`.
void poke_double(hid_t file, const char* where, hsize_t flat, double value) {
  const hid_t d = H5Dopen2(file, where, H5P_DEFAULT);
  const hid_t s = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  std::vector<double> v(static_cast<size_t>(n));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  v[flat] = value;
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s);
  H5Dclose(d);
}

ChildResult read_in_child(const std::string& path) {
  return icobrdf::test::run_in_child([&] { icobrdf::read_bank(path); }, kChildTimeoutSeconds);
}

// The read ended in `kind` with a one-line message naming the file and every string of `parts`, quietly.
void expect_refused(const ChildResult& r, const std::string& path, const std::vector<std::string>& parts,
                    const std::string& kind = "InputError") {
  if (std::getenv("ICOBRDF_TEST_SHOW_ERRORS")) std::printf("    %s: %s\n", r.kind.c_str(), r.message.c_str());
  EXPECT_FALSE(r.timed_out) << "reader hung";
  EXPECT_FALSE(r.signaled) << "reader crashed";
  EXPECT_EQ(r.kind, kind) << r.message;
  EXPECT_EQ(r.message.find('\n'), std::string::npos) << "message is not one line: " << r.message;
  EXPECT_EQ(r.message.rfind(path, 0), 0u) << "message does not start with the file: " << r.message;
  for (const auto& p : parts) EXPECT_NE(r.message.find(p), std::string::npos) << "missing '" << p << "' in: " << r.message;
  EXPECT_EQ(r.err, "") << "stderr not empty";
}

// A fresh valid file in a scratch folder for every test, written by `write`.
class CorruptFile : public ::testing::Test {
 protected:
  CorruptFile(void (*write)(const std::string&), const char* file) : write_(write), file_(file) {}
  void SetUp() override { rewrite(); }
  void rewrite() {
    path_ = dir_ / file_;
    write_(path_);
  }
  ScratchDir dir_;
  std::string path_;

 private:
  void (*write_)(const std::string&);
  const char* file_;
};

class CorruptBank : public CorruptFile {
 protected:
  CorruptBank() : CorruptFile(write_valid_bank, "bank.h5") {}
};

TEST_F(CorruptBank, ValidBankReadsInChild) {
  const auto r = read_in_child(path_);
  EXPECT_EQ(r.kind, "ok") << r.message;
  EXPECT_EQ(r.err, "");
}

TEST_F(CorruptBank, MissingFileIsIoError) {
  expect_refused(read_in_child(dir_ / "absent.h5"), dir_ / "absent.h5", {"No such file"}, "IoError");
}

TEST_F(CorruptBank, FolderIsRefused) { expect_refused(read_in_child(dir_.path()), dir_.path(), {"expected a regular file"}); }

TEST_F(CorruptBank, NotHdf5) {
  icobrdf::test::write_bytes(path_, "theta_i,phi_i,theta_r,phi_r,value\n0,0,0,0,0.3\n");
  expect_refused(read_in_child(path_), path_, {"expected an HDF5 file"});
}

TEST_F(CorruptBank, EmptyFile) {
  icobrdf::test::write_bytes(path_, "");
  expect_refused(read_in_child(path_), path_, {"expected an HDF5 file", "0 bytes"});
}

TEST_F(CorruptBank, SignatureFollowedByGarbage) {
  std::string bytes = icobrdf::test::read_bytes(path_).substr(0, 8);
  for (int i = 0; i < 4096; ++i) bytes.push_back(static_cast<char>((i * 2654435761u) >> 13));
  icobrdf::test::write_bytes(path_, bytes);
  expect_refused(read_in_child(path_), path_, {"cannot open as HDF5"});
}

TEST_F(CorruptBank, TruncatedAt10_50_99Percent) {
  const std::string full = icobrdf::test::read_bytes(path_);
  for (int percent : {10, 50, 99}) {
    const std::string p = dir_ / ("cut" + std::to_string(percent) + ".h5");
    icobrdf::test::write_bytes(p, full.substr(0, full.size() * percent / 100));
    SCOPED_TRACE(percent);
    expect_refused(read_in_child(p), p, {});
  }
}

TEST_F(CorruptBank, MissingDataset) {
  mutate(path_, [](hid_t f) { H5Ldelete(f, "/materials/m/C", H5P_DEFAULT); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "missing dataset"});
}

TEST_F(CorruptBank, MissingGridDataset) {
  mutate(path_, [](hid_t f) { H5Ldelete(f, "/grid/cubature_weights", H5P_DEFAULT); });
  expect_refused(read_in_child(path_), path_, {"/grid/cubature_weights", "missing dataset"});
}

TEST_F(CorruptBank, WrongShape) {
  std::vector<double> zeros(3 * 6 * 5, 0.0);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/materials/m/C", H5T_IEEE_F64LE, {3, 6, 5}, zeros.data()); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected shape 3 x 6 x 6, found 3 x 6 x 5"});
}

TEST_F(CorruptBank, WrongRank) {
  std::vector<double> zeros(3 * 36, 0.0);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/materials/m/C", H5T_IEEE_F64LE, {3, 36}, zeros.data()); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected shape 3 x 6 x 6, found 3 x 36"});
}

TEST_F(CorruptBank, WrongDtype) {
  std::vector<std::int32_t> zeros(3 * 36, 0);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/materials/m/C", H5T_STD_I32LE, {3, 6, 6}, zeros.data()); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected float64", "4-byte signed integer"});
}

TEST_F(CorruptBank, Float32CoefficientsRefused) {
  std::vector<float> zeros(3 * 36, 0.0f);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/materials/m/C", H5T_IEEE_F32LE, {3, 6, 6}, zeros.data()); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected float64, found a 4-byte float"});
}

TEST_F(CorruptBank, WrongIndexDtype) {
  std::vector<double> offsets(9, 0.0);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/grid/cubature_offsets", H5T_IEEE_F64LE, {9}, offsets.data()); });
  expect_refused(read_in_child(path_), path_, {"/grid/cubature_offsets", "expected int64, found an 8-byte float"});
}

TEST_F(CorruptBank, NewerMajorVersion) {
  mutate(path_, [](hid_t f) { set_string_attr(f, "format_version", "5.0"); });
  expect_refused(read_in_child(path_), path_, {"newer", "5.0", "expected major version 1 to 4"});
}

TEST_F(CorruptBank, NewerMinorVersionIsAccepted) {
  mutate(path_, [](hid_t f) { set_string_attr(f, "format_version", "1.7"); });
  EXPECT_EQ(read_in_child(path_).kind, "ok");
}

TEST_F(CorruptBank, MalformedVersion) {
  mutate(path_, [](hid_t f) { set_string_attr(f, "format_version", "one"); });
  expect_refused(read_in_child(path_), path_, {"format_version", "expected MAJOR.MINOR", "one"});
}

TEST_F(CorruptBank, ForeignFormat) {
  mutate(path_, [](hid_t f) { set_string_attr(f, "format", "someone-else"); });
  expect_refused(read_in_child(path_), path_, {"expected 'icobrdf-bank'", "someone-else"});
}

TEST_F(CorruptBank, IncompleteWrite) {
  mutate(path_, [](hid_t f) { H5Adelete(f, "complete"); });
  expect_refused(read_in_child(path_), path_, {"complete", "did not finish"});
}

TEST_F(CorruptBank, AbsurdDeclaredSizeRefusedBeforeAllocating) {
  // 3 x 200000 x 200000 float64 = 9.6e11 bytes declared, none written (chunks are allocated lazily).
  mutate(path_, [](hid_t f) {
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    const hsize_t chunk[3] = {1, 1, 1000};
    H5Pset_chunk(dcpl, 3, chunk);
    replace_dataset(f, "/materials/m/lut", H5T_IEEE_F64LE, {3, 200000, 200000}, nullptr, dcpl);
    H5Pclose(dcpl);
  });
  expect_refused(read_in_child(path_), path_, {"/materials/m/lut", "960000000000 bytes", "limit of 4294967296 bytes"});
}

// A file of a few kB can declare hundreds of MB of compressed (here unwritten) chunks: the read is held to the
// memory budget before it allocates, and the line names the dataset and its declared shape.
TEST_F(CorruptBank, DeclaredSizeBeyondTheMemoryBudgetRefusedBeforeAllocating) {
  constexpr double kBudgetBytes = 150e6;  // between the two declared LUTs below (128 MB and 200 MB)
  const auto declare_lut = [&](hsize_t cells) {
    mutate(path_, [&](hid_t f) {
      const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
      const hsize_t chunk[3] = {1, 100, 100};
      H5Pset_chunk(dcpl, 3, chunk);
      replace_dataset(f, "/materials/big/lut", H5T_IEEE_F64LE, {1, cells, cells}, nullptr, dcpl);
      H5Pclose(dcpl);
    });
  };
  const auto read_with_budget = [&] {
    return icobrdf::test::run_in_child([&] {
      icobrdf::set_memory_budget(kBudgetBytes);
      icobrdf::read_bank(path_);
    }, kChildTimeoutSeconds);
  };
  declare_lut(5000);  // 200 MB
  expect_refused(read_with_budget(), path_, {"/materials/big/lut", "declared shape 1 x 5000 x 5000", "150 MB is available (memory budget)"},
                 "ResourceError");
  rewrite();
  declare_lut(4000);  // 128 MB: within the budget, read (its unwritten chunks are zeros)
  EXPECT_EQ(read_with_budget().kind, "ok");
}

TEST_F(CorruptBank, ReadLimitIsConfigurable) {
  // The big LUT holds 12800 bytes; a 10000-byte limit refuses it.
  const auto r = icobrdf::test::run_in_child([&] {
    icobrdf::ReadOptions o;
    o.max_dataset_bytes = 10000;
    icobrdf::read_bank(path_, o);
  });
  expect_refused(r, path_, {"/materials/big/lut", "12800 bytes", "limit of 10000 bytes"});
}

TEST_F(CorruptBank, NaNInC) {
  mutate(path_, [](hid_t f) { poke_double(f, "/materials/m/C", 36 + 6 * 2 + 4, std::nan("")); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected finite", "channel 1, row 2, column 4"});
}

TEST_F(CorruptBank, NaNInLut) {
  mutate(path_, [](hid_t f) { poke_double(f, "/materials/m/lut", 64 * 2 + 8 * 7 + 1, std::nan("")); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/lut", "expected finite", "channel 2, incident cell 7, remitted cell 1"});
}

TEST_F(CorruptBank, NaNInGrid) {
  mutate(path_, [](hid_t f) { poke_double(f, "/grid/directions", 5, std::nan("")); });
  expect_refused(read_in_child(path_), path_, {"/grid/directions", "expected finite"});
}

// Flips one byte in the middle of the stored bytes of chunk 0 of `where`.
void flip_chunk_byte(const std::string& path, const char* where) {
  haddr_t addr = 0;
  hsize_t size = 0;
  mutate(path, [&](hid_t f) {
    const hid_t d = H5Dopen2(f, where, H5P_DEFAULT);
    const hid_t s = H5Dget_space(d);
    hsize_t offset[3];
    unsigned mask = 0;
    ASSERT_GE(H5Dget_chunk_info(d, s, 0, offset, &mask, &addr, &size), 0);
    H5Sclose(s);
    H5Dclose(d);
  });
  ASSERT_GT(size, 8u);
  std::string bytes = icobrdf::test::read_bytes(path);
  ASSERT_LT(addr + size, bytes.size());
  bytes[addr + size / 2] ^= 0x10;
  icobrdf::test::write_bytes(path, bytes);
}

TEST_F(CorruptBank, BitFlipInChecksummedChunk) {
  flip_chunk_byte(path_, "/materials/m/C");  // Fletcher32 only (864 bytes)
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "cannot read the data", "Fletcher32"});
}

TEST_F(CorruptBank, BitFlipInCompressedChunk) {
  flip_chunk_byte(path_, "/materials/big/lut");  // shuffle + deflate + Fletcher32
  expect_refused(read_in_child(path_), path_, {"/materials/big/lut", "cannot read the data", "Fletcher32"});
}

TEST_F(CorruptBank, ExternalLinkRefused) {
  mutate(path_, [](hid_t f) { H5Lcreate_external("/etc/passwd", "/x", f, "/materials/evil", H5P_DEFAULT, H5P_DEFAULT); });
  expect_refused(read_in_child(path_), path_, {"/materials/evil", "expected a hard link, found an external link"});
}

TEST_F(CorruptBank, SoftLinkRefused) {
  mutate(path_, [](hid_t f) {
    H5Ldelete(f, "/materials/m/C", H5P_DEFAULT);
    H5Lcreate_soft("/materials/big/C", f, "/materials/m/C", H5P_DEFAULT, H5P_DEFAULT);
  });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected a hard link, found a soft link"});
}

TEST_F(CorruptBank, ExternalStorageRefused) {
  mutate(path_, [](hid_t f) {
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_external(dcpl, "raw.bin", 0, 3 * 36 * 8);
    replace_dataset(f, "/materials/m/C", H5T_IEEE_F64LE, {3, 6, 6}, nullptr, dcpl);
    H5Pclose(dcpl);
  });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "external storage"});
}

TEST_F(CorruptBank, UnexpectedFilterRefused) {
  std::vector<double> zeros(3 * 36, 0.0);
  mutate(path_, [&](hid_t f) {
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    const hsize_t chunk[3] = {1, 6, 6};
    H5Pset_chunk(dcpl, 3, chunk);
    H5Pset_scaleoffset(dcpl, H5Z_SO_FLOAT_DSCALE, 3);
    replace_dataset(f, "/materials/m/C", H5T_IEEE_F64LE, {3, 6, 6}, zeros.data(), dcpl);
    H5Pclose(dcpl);
  });
  expect_refused(read_in_child(path_), path_, {"/materials/m/C", "expected only deflate, shuffle and Fletcher32", "filter id 6"});
}

TEST_F(CorruptBank, OrderDisagreesWithC) {
  mutate(path_, [](hid_t f) {
    const hid_t g = H5Gopen2(f, "/materials/m", H5P_DEFAULT);
    const int order = 3;
    const hid_t a = H5Aopen(g, "order", H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_INT, &order);
    H5Aclose(a);
    H5Gclose(g);
  });
  expect_refused(read_in_child(path_), path_, {"/materials/m", "attribute modes: expected 10 for order 3, found 6"});
}

TEST_F(CorruptBank, LutDisagreesWithGrid) {
  std::vector<double> ones(3 * 7 * 7, 1.0);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/materials/m/lut", H5T_IEEE_F64LE, {3, 7, 7}, ones.data()); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/lut", "expected 8 cells as in /grid, found 7"});
}

TEST_F(CorruptBank, GridOffsetsNotIncreasing) {
  std::vector<std::int64_t> offsets = {0, 1, 2, 2, 4, 6, 8, 10, 12};
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/grid/cubature_offsets", H5T_STD_I64LE, {9}, offsets.data()); });
  expect_refused(read_in_child(path_), path_, {"/grid/cubature_offsets", "expected strictly increasing"});
}

TEST_F(CorruptBank, GridFaceIndexOutOfRange) {
  std::vector<std::int32_t> faces(24, 0);
  faces[7] = 8;  // only 8 vertices
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/grid/faces", H5T_STD_I32LE, {8, 3}, faces.data()); });
  expect_refused(read_in_child(path_), path_, {"/grid/faces", "expected indices in [0, 8), found 8"});
}

TEST_F(CorruptBank, GridFailingValidation) {
  mutate(path_, [](hid_t f) { poke_double(f, "/grid/solid_angles", 2, 2.0); });  // weights no longer sum to it
  expect_refused(read_in_child(path_), path_, {"/grid", "cubature weights of cell 2"});
}

TEST_F(CorruptBank, IbsssWithoutIndices) {
  std::vector<double> v(3 * 5, 0.5);
  mutate(path_, [&](hid_t f) { replace_dataset(f, "/materials/m/ibsss", H5T_IEEE_F64LE, {3, 5}, v.data()); });
  expect_refused(read_in_child(path_), path_, {"/materials/m/ibsss_indices", "missing dataset"});
}

// A bank whose material "lobe" is a half-angle lobe alone (all-zero C) on a stretched anisotropic grid, so
// that every format 3.0 attribute of /materials/lobe/half_angle is present.
void write_lobe_bank(const std::string& path) {
  icobrdf::MaterialRecord m;
  m.name = "lobe";
  m.spectrum = icobrdf::test::synthetic_spectrum(0, 1);
  m.spectrum.channels[0].setZero();
  icobrdf::HalfAngleFactors f;
  f.quantity = icobrdf::HalfAngleQuantity::MeanCosine;
  f.isotropic = false;
  f.h_axis = 0.5, f.h_scale_1 = 2.0;
  f.n_t = 4, f.n_phi_h = 4, f.n_theta_d = 4, f.n_phi_d = 2, f.rank = 1;
  f.u.emplace_back(icobrdf::RowMatrixXd::Constant(16, 1, 0.5));
  f.v.emplace_back(icobrdf::RowMatrixXd::Constant(8, 1, 2.0));
  m.lobe = f;
  icobrdf::BankContents b;
  b.materials = {m};
  icobrdf::write_bank(path, b);
}

class CorruptLobe : public CorruptFile {
 protected:
  CorruptLobe() : CorruptFile(write_lobe_bank, "lobe.h5") {}
  // Set a string or a float64 attribute of the lobe group and expect the read refused naming it.
  void expect_string_refused(const char* name, const std::string& value, const std::vector<std::string>& parts) {
    mutate(path_, [&](hid_t file) {
      const hid_t g = H5Gopen2(file, "/materials/lobe/half_angle", H5P_DEFAULT);
      set_string_attr(g, name, value);
      H5Gclose(g);
    });
    expect_refused(read_in_child(path_), path_, parts);
  }
  void expect_double_refused(const char* name, double value, const std::vector<std::string>& parts) {
    mutate(path_, [&](hid_t file) {
      const hid_t g = H5Gopen2(file, "/materials/lobe/half_angle", H5P_DEFAULT);
      const hid_t a = H5Aopen(g, name, H5P_DEFAULT);
      H5Awrite(a, H5T_NATIVE_DOUBLE, &value);
      H5Aclose(a);
      H5Gclose(g);
    });
    expect_refused(read_in_child(path_), path_, parts);
  }
};

TEST_F(CorruptLobe, ValidLobeBankReadsInChild) {
  const auto r = read_in_child(path_);
  EXPECT_EQ(r.kind, "ok") << r.message;
}

TEST_F(CorruptLobe, UnknownQuantityCornersOrNodesAreRefused) {
  expect_string_refused("quantity", "median-cosine", {"half_angle", "attribute quantity", "median-cosine"});
  rewrite();
  expect_string_refused("corners", "some", {"half_angle", "attribute corners", "'valid'", "some"});
  rewrite();
  expect_string_refused("nodes", "middles", {"half_angle", "attribute nodes", "'centres'", "middles"});
}

TEST_F(CorruptLobe, StretchOutOfRangeIsRefused) {
  expect_double_refused("h_scale_1", 0.0, {"half_angle", "h scale 0"});
  rewrite();
  expect_double_refused("h_scale_2", 1e9, {"half_angle", "h scale 1e+09"});
  rewrite();
  expect_double_refused("h_axis", 4.0, {"half_angle", "h_axis = 4"});
}

}  // namespace ICOBRDF_UNITY_ID
