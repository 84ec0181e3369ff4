// Inputs that once escaped the bank validator with an exception other than InputError (found by fuzzing,
// fuzz/fuzz_bank.cpp). Each read runs in a child with a timeout, as in test_bank_corrupt.cpp.
#include <gtest/gtest.h>

#include "icobrdf/io/bank_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;

// A read of a small bank that takes longer than this is treated as hung.
constexpr double kChildTimeoutSeconds = 20.0;

void write_small_bank(const std::string& path) {
  icobrdf::BankContents b;
  icobrdf::MaterialRecord m;
  m.name = "m";
  m.spectrum = icobrdf::test::synthetic_spectrum(1, 1);
  b.materials = {m};
  icobrdf::write_bank(path, b);
}

void set_root_string_attr(const std::string& path, const char* name, const std::string& value) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  H5Adelete(f, name);
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, value.size() + 1);
  const hid_t s = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(f, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(a, 0);
  H5Awrite(a, t, value.c_str());
  H5Aclose(a);
  H5Sclose(s);
  H5Tclose(t);
  ASSERT_GE(H5Fclose(f), 0);
}

// format_version digits beyond int range used to throw std::out_of_range from std::stoi ("internal error").
TEST(BankFuzzRegressions, VersionNumbersBeyondIntAreInputErrors) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  for (const std::string v : {"99999999999999.1", "1.99999999999999", "0000000001.0"}) {
    write_small_bank(path);
    set_root_string_attr(path, "format_version", v);
    const auto r = icobrdf::test::run_in_child([&] { icobrdf::read_bank(path); }, kChildTimeoutSeconds);
    EXPECT_EQ(r.kind, "InputError") << v << ": " << r.message;
    EXPECT_NE(r.message.find("format_version: expected MAJOR.MINOR, found '" + v + "'"), std::string::npos) << r.message;
    EXPECT_EQ(r.err, "");
  }
}

// Link names and string attributes may hold control bytes; they used to reach the message verbatim, so a
// newline in a link name made the InputError span several lines. They are now written as \xHH.
TEST(BankFuzzRegressions, ControlBytesInNamesAndValuesKeepMessagesOnOneLine) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  write_small_bank(path);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_GE(H5Lcreate_soft("/materials", f, "a\nb", H5P_DEFAULT, H5P_DEFAULT), 0);
    ASSERT_GE(H5Fclose(f), 0);
  }
  auto r = icobrdf::test::run_in_child([&] { icobrdf::read_bank(path); }, kChildTimeoutSeconds);
  EXPECT_EQ(r.kind, "InputError") << r.message;
  EXPECT_NE(r.message.find("/a\\x0ab: expected a hard link, found a soft link"), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find('\n'), std::string::npos) << r.message;

  write_small_bank(path);
  set_root_string_attr(path, "format", "icobrdf\r\nbank");
  r = icobrdf::test::run_in_child([&] { icobrdf::read_bank(path); }, kChildTimeoutSeconds);
  EXPECT_EQ(r.kind, "InputError") << r.message;
  EXPECT_NE(r.message.find("found 'icobrdf\\x0d\\x0abank'"), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find('\n'), std::string::npos) << r.message;
}

}  // namespace
