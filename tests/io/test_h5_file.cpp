// The HDF5 layer (icobrdf/io/h5_file.hpp) against the raw HDF5 C API: typed writes land with the documented
// element types, row-major orientation and filters; reads refuse wrong kinds, types, ranks, sizes and
// attribute forms with one-line InputErrors; big-endian data written by other tools is converted.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/h5_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::h5::Group;
using icobrdf::h5::ReadFile;
using icobrdf::h5::ReadLimits;
using icobrdf::h5::Shape;
using icobrdf::h5::ShapePattern;
using icobrdf::h5::WriteFile;
using icobrdf::test::ScratchDir;

// Raw read of a whole float64 dataset.
std::vector<double> raw_doubles(const std::string& file, const char* where, std::vector<hsize_t>* dims = nullptr) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, where, H5P_DEFAULT);
  const hid_t s = H5Dget_space(d);
  std::vector<double> v(static_cast<size_t>(H5Sget_simple_extent_npoints(s)));
  if (dims) {
    dims->resize(static_cast<size_t>(H5Sget_simple_extent_ndims(s)));
    H5Sget_simple_extent_dims(s, dims->data(), nullptr);
  }
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s);
  H5Dclose(d);
  H5Fclose(f);
  return v;
}

bool stored_type_is(const std::string& file, const char* where, hid_t expected) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, where, H5P_DEFAULT);
  const hid_t t = H5Dget_type(d);
  const bool eq = H5Tequal(t, expected) > 0;
  H5Tclose(t);
  H5Dclose(d);
  H5Fclose(f);
  return eq;
}

// Writes a small file through the layer: root attributes of every kind and datasets of every type.
void write_sample(const std::string& path) {
  WriteFile f = WriteFile::create(path, path);
  {
    Group r = f.root();
    r.set_attr("s", "text");
    r.set_attr("d", 2.5);
    r.set_attr("i32", std::int32_t{-7});
    r.set_attr("i64", std::int64_t{1} << 40);
    r.set_attr("b", true);
    r.set_attr("two", std::int32_t{2});
    Group g = r.create_group("g");
    const double d[6] = {1, 2, 3, 4, 5, 6};
    const float fl[3] = {0.5f, 1.5f, 2.5f};
    const std::int32_t i[4] = {-1, 0, 1, 2};
    const std::int64_t l[2] = {-(std::int64_t{1} << 50), 3};
    const std::uint8_t u[3] = {0, 1, 255};
    g.write("d", d, Shape{2, 3}, "sr", "doubles");
    g.write("f", fl, Shape{3}, "1/sr");
    g.write("i", i, Shape{2, 2}, "index");
    g.write("l", l, Shape{2}, "index");
    g.write("u", u, Shape{3}, "1");
    Eigen::MatrixXd m(2, 3);  // column-major in memory
    m << 1, 2, 3, 4, 5, 6;
    g.write_matrix("m", m, "1", "a 2 x 3 matrix");
    // 300 x 1000 float64 = 2.4 MB: more than one 1 MiB chunk.
    std::vector<double> big(300 * 1000);
    for (size_t k = 0; k < big.size(); ++k) big[k] = std::sqrt(static_cast<double>(k));
    g.write("big", big.data(), Shape{300, 1000}, "1");
  }
  f.finish();
}

class H5Layer : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_ / "sample.h5";
    write_sample(path_);
  }
  ScratchDir dir_;
  std::string path_;
  ReadLimits lim_;
};

template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const icobrdf::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST_F(H5Layer, StoredTypesAreTheDocumentedLittleEndianOnes) {
  EXPECT_TRUE(stored_type_is(path_, "/g/d", H5T_IEEE_F64LE));
  EXPECT_TRUE(stored_type_is(path_, "/g/f", H5T_IEEE_F32LE));
  EXPECT_TRUE(stored_type_is(path_, "/g/i", H5T_STD_I32LE));
  EXPECT_TRUE(stored_type_is(path_, "/g/l", H5T_STD_I64LE));
  EXPECT_TRUE(stored_type_is(path_, "/g/u", H5T_STD_U8LE));
}

TEST_F(H5Layer, MatricesAreStoredRowMajor) {
  std::vector<hsize_t> dims;
  const auto v = raw_doubles(path_, "/g/m", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(v, (std::vector<double>{1, 2, 3, 4, 5, 6}));  // m(0, 1) = 2 is the second stored value
}

TEST_F(H5Layer, LargeDatasetChunksStayWithinTarget) {
  const hid_t f = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "/g/big", H5P_DEFAULT);
  const hid_t p = H5Dget_create_plist(d);
  hsize_t chunk[2] = {0, 0};
  ASSERT_EQ(H5Pget_chunk(p, 2, chunk), 2);
  EXPECT_EQ(chunk[1], 1000u);  // whole rows
  EXPECT_LE(chunk[0] * chunk[1] * 8, icobrdf::h5::kChunkTargetBytes);
  EXPECT_GE(chunk[0] * chunk[1] * 8 * 2, icobrdf::h5::kChunkTargetBytes);  // not needlessly small
  H5Pclose(p);
  H5Dclose(d);
  H5Fclose(f);
  const auto r = ReadFile::open(path_);
  const auto a = r.root().open_group("g").read<double>("big", ShapePattern{300, 1000}, lim_);
  EXPECT_EQ(a.data[123456], std::sqrt(123456.0));
}

TEST_F(H5Layer, TypedReadsRoundTrip) {
  const auto r = ReadFile::open(path_);
  const Group root = r.root();
  EXPECT_EQ(root.attr_string("s"), "text");
  EXPECT_EQ(root.attr_double("d"), 2.5);
  EXPECT_EQ(root.attr_int("i32", -10, 10), -7);
  EXPECT_EQ(root.attr_int("i64", 0, std::int64_t{1} << 41), std::int64_t{1} << 40);
  EXPECT_TRUE(root.attr_bool("b"));
  EXPECT_TRUE(root.attr_bool("complete"));
  const Group g = root.open_group("g");
  EXPECT_EQ(g.read<double>("d", ShapePattern{2, 3}, lim_).data, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(g.read<float>("f", ShapePattern{-1}, lim_).data, (std::vector<float>{0.5f, 1.5f, 2.5f}));
  EXPECT_EQ(g.read_real("f", ShapePattern{3}, lim_).data, (std::vector<double>{0.5, 1.5, 2.5}));
  EXPECT_EQ(g.read<std::int32_t>("i", ShapePattern{-1, 2}, lim_).data, (std::vector<std::int32_t>{-1, 0, 1, 2}));
  EXPECT_EQ(g.read<std::int64_t>("l", ShapePattern{2}, lim_).data, (std::vector<std::int64_t>{-(std::int64_t{1} << 50), 3}));
  EXPECT_EQ(g.read<std::uint8_t>("u", ShapePattern{3}, lim_).data, (std::vector<std::uint8_t>{0, 1, 255}));
  EXPECT_EQ(g.attributes_of("d").attr_string("unit"), "sr");
  EXPECT_EQ(g.attributes_of("d").attr_string("description"), "doubles");
  EXPECT_EQ(g.children(), (std::vector<std::string>{"big", "d", "f", "i", "l", "m", "u"}));
}

TEST_F(H5Layer, RefusalsNameFileObjectExpectedAndFound) {
  const auto r = ReadFile::open(path_);
  const Group root = r.root();
  const Group g = root.open_group("g");
  EXPECT_EQ(input_error_of([&] { g.read<double>("i", ShapePattern{2, 2}, lim_); }),
            path_ + ": /g/i: expected float64, found a 4-byte signed integer");
  EXPECT_EQ(input_error_of([&] { g.read<double>("d", ShapePattern{3, 2}, lim_); }),
            path_ + ": /g/d: expected shape 3 x 2, found 2 x 3");
  EXPECT_EQ(input_error_of([&] { g.read<double>("f", ShapePattern{3}, lim_); }),
            path_ + ": /g/f: expected float64, found a 4-byte float");
  EXPECT_EQ(input_error_of([&] { g.read<std::int64_t>("i", ShapePattern{2, 2}, lim_); }),
            path_ + ": /g/i: expected int64, found a 4-byte signed integer");
  EXPECT_EQ(input_error_of([&] { root.open_group("nothing"); }), path_ + ": /nothing: missing group");
  EXPECT_EQ(input_error_of([&] { g.open_group("d"); }), path_ + ": /g/d: expected a group, found a dataset");
  EXPECT_EQ(input_error_of([&] { root.read<double>("g", ShapePattern{1}, lim_); }), path_ + ": /g: expected a dataset, found a group");
  EXPECT_EQ(input_error_of([&] { root.attr_double("s"); }), path_ + ": /: attribute s: expected float64, found a 5-byte string");
  EXPECT_EQ(input_error_of([&] { root.attr_int("i32", 0, 10); }), path_ + ": /: attribute i32: expected a value in [0, 10], found -7");
  EXPECT_EQ(input_error_of([&] { root.attr_bool("i32"); }), path_ + ": /: attribute i32: expected uint8 0/1, found a 4-byte signed integer");
  EXPECT_EQ(input_error_of([&] { root.attr_string("absent"); }), path_ + ": /: missing attribute absent");
  ReadLimits tight{1000};
  EXPECT_EQ(input_error_of([&] { g.read<double>("big", ShapePattern{300, 1000}, tight); }),
            path_ + ": /g/big: declares shape 300 x 1000 (2400000 bytes), expected at most the limit of 1000 bytes");
}

TEST_F(H5Layer, Float32ReadAsFloat64CountsMemoryBytesAgainstTheLimit) {
  // /g/f: 3 float32 = 12 bytes stored, 24 bytes as float64.
  const auto r = ReadFile::open(path_);
  const Group g = r.root().open_group("g");
  EXPECT_NO_THROW(g.read_real("f", ShapePattern{3}, ReadLimits{24}));
  EXPECT_EQ(input_error_of([&] { g.read_real("f", ShapePattern{3}, ReadLimits{20}); }),
            path_ + ": /g/f: needs 24 bytes in memory, expected at most the limit of 20");
}

TEST_F(H5Layer, AttributeFormsOtherToolsWriteAreRefused) {
  const hid_t f = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  {  // array attribute where a scalar is expected
    const hsize_t n = 2;
    const hid_t s = H5Screate_simple(1, &n, nullptr);
    const double v[2] = {1, 2};
    const hid_t a = H5Acreate2(f, "arr", H5T_IEEE_F64LE, s, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, v);
    H5Aclose(a);
    H5Sclose(s);
  }
  {  // variable-length string (h5py's default for str)
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    const hid_t s = H5Screate(H5S_SCALAR);
    const char* v = "vlen";
    const hid_t a = H5Acreate2(f, "vlen", t, s, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, t, &v);
    H5Aclose(a);
    H5Sclose(s);
    H5Tclose(t);
  }
  {  // boolean stored as 2
    const std::uint8_t two = 2;
    const hid_t s = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, "bool2", H5T_STD_U8LE, s, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_UINT8, &two);
    H5Aclose(a);
    H5Sclose(s);
  }
  H5Fclose(f);
  const auto r = ReadFile::open(path_);
  const Group root = r.root();
  EXPECT_EQ(input_error_of([&] { root.attr_double("arr"); }),
            path_ + ": /: attribute arr: expected a scalar, found an array or empty dataspace");
  EXPECT_EQ(input_error_of([&] { root.attr_string("vlen"); }),
            path_ + ": /: attribute vlen: expected a fixed-length string, found a variable-length string");
  EXPECT_EQ(input_error_of([&] { root.attr_bool("bool2"); }), path_ + ": /: attribute bool2: expected 0 or 1, found 2");
}

TEST_F(H5Layer, BigEndianDataIsConverted) {
  const hid_t f = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hsize_t n = 3;
  const hid_t s = H5Screate_simple(1, &n, nullptr);
  const double v[3] = {1.0 / 3.0, -2.0, 1e300};
  const hid_t d = H5Dcreate2(f, "/g/be", H5T_IEEE_F64BE, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
  H5Dclose(d);
  H5Sclose(s);
  H5Fclose(f);
  const auto r = ReadFile::open(path_);
  EXPECT_EQ(r.root().open_group("g").read<double>("be", ShapePattern{3}, lim_).data, (std::vector<double>(v, v + 3)));
}

TEST(H5LayerBank, MaterialArraysHaveTheDocumentedOrientation) {
  // A non-symmetric C and LUT, read with the raw API: C[c, a, b] = channel c's (a, b), lut[c, i, r] = (i, r).
  ScratchDir dir;
  icobrdf::BankContents b;
  icobrdf::MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(1, 3);
  m.spectrum.grid_kind = "test-cells";
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd f(4, 4);
    for (int i = 0; i < 4; ++i)
      for (int r = 0; r < 4; ++r) f(i, r) = 100 * c + 10 * i + r;
    m.lut.push_back(f);
  }
  b.materials = {m};
  b.grid = icobrdf::test::synthetic_grid();
  icobrdf::write_bank(dir / "b.h5", b);
  const auto lut = raw_doubles(dir / "b.h5", "/materials/m/lut");
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 4; ++i)
      for (int r = 0; r < 4; ++r) EXPECT_EQ(lut[(c * 4 + i) * 4 + r], 100 * c + 10 * i + r);
  const auto cc = raw_doubles(dir / "b.h5", "/materials/m/C");
  const auto& s = m.spectrum;
  ASSERT_NE(s.channels[1](0, 2), s.channels[1](2, 0));
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(cc[(c * 3 + a) * 3 + k], s.channels[c](a, k));
  const auto dirs = raw_doubles(dir / "b.h5", "/grid/directions");
  for (int cell = 0; cell < 8; ++cell)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(dirs[cell * 3 + k], b.grid->directions(cell, k));
}

}  // namespace ICOBRDF_UNITY_ID
