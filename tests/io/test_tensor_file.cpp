// Tensor files (icobrdf/io/tensor_file.hpp): the writer and the reader agree, the byte layout is the documented one
// (checked on a file assembled here byte by byte), and malformed files give one-line InputErrors.
#include <gtest/gtest.h>

#include <cstring>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/tensor_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ScratchDir;

std::string le_bytes(std::uint64_t v, int n) {
  std::string s;
  for (int k = 0; k < n; ++k) s.push_back(static_cast<char>(v >> (8 * k)));
  return s;
}

// A file with one field "h" of float16 [3] = {1, -2, 2^-24} at offset 48, assembled by hand.
std::string hand_made_file() {
  std::string s("tensor_file\0", 12);
  s += std::string("\x01\x00", 2) + le_bytes(1, 4);
  s += le_bytes(1, 2) + "h" + le_bytes(1, 2) + std::string(1, 9) + le_bytes(48, 8) + le_bytes(3, 8);
  s.resize(48, '\0');
  s += le_bytes(0x3C00, 2) + le_bytes(0xC000, 2) + le_bytes(0x0001, 2);
  return s;
}

TEST(TensorFile, ReadsAHandMadeFile) {
  ScratchDir d;
  test::write_bytes(d / "a.tensor", hand_made_file());
  const TensorFile tf = read_tensor_file(d / "a.tensor");
  ASSERT_EQ(tf.fields.size(), 1u);
  const TensorField* f = tf.find("h");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->dtype, TensorDtype::Float16);
  EXPECT_EQ(f->shape_text(), "[3]");
  const std::vector<double> v = f->values();
  EXPECT_EQ(v[0], 1.0);
  EXPECT_EQ(v[1], -2.0);
  EXPECT_EQ(v[2], std::ldexp(1.0, -24));
}

TEST(TensorFile, WriterAndReaderAgree) {
  ScratchDir d;
  const std::vector<TensorField> in = {text_field("description", "x y"), float32_field("t", {2, 3}, {0, 0.5, -1, 2, 1e30, 3.25}),
                                       uint8_field("flag", {1}, {1})};
  write_tensor_file(d / "b.tensor", in);
  const std::string bytes = test::read_bytes(d / "b.tensor");
  EXPECT_EQ(bytes.substr(0, 14), std::string("tensor_file\0\x01\x00", 14));
  const TensorFile tf = read_tensor_file(d / "b.tensor");
  ASSERT_EQ(tf.fields.size(), 3u);
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(tf.fields[i].name, in[i].name);
    EXPECT_EQ(tf.fields[i].dtype, in[i].dtype);
    EXPECT_EQ(tf.fields[i].shape, in[i].shape);
    EXPECT_EQ(tf.fields[i].bytes, in[i].bytes);
  }
  const std::vector<double> t = tf.find("t")->values();
  EXPECT_EQ(t[1], 0.5);
  EXPECT_EQ(t[4], static_cast<double>(1e30f));
}

std::string message_of(const std::string& file) {
  return test::input_error_of(file, [&] { read_tensor_file(file); });
}

TEST(TensorFile, MalformedFilesGiveOneLineErrors) {
  ScratchDir d;
  const std::string good = hand_made_file(), f = d / "bad.tensor";
  auto check = [&](const std::string& bytes, const std::string& expected) {
    test::write_bytes(f, bytes);
    const std::string m = message_of(f);
    EXPECT_NE(m.find(expected), std::string::npos) << m;
  };
  check(good.substr(0, 10), "too short: 10 bytes, expected at least 18");
  std::string b = good;
  b[0] = 'T';
  check(b, "not a tensor file");
  b = good;
  b[12] = 2;
  check(b, "version 2.0 is not supported, expected 1.0");
  b = good;
  b[23] = 12;  // dtype byte of field 0
  check(b, "field 0 'h': unknown dtype code 12");
  check(good.substr(0, good.size() - 1), "field 0 'h': data of 6 bytes at offset 48 runs past the end of the file (53 bytes)");
  b = good;
  b[14] = 2;  // two fields declared; the second header starts inside the padding: empty name
  check(b, "field 1 has an empty name");
  b = good;
  b[14] = static_cast<char>(0xff);
  check(b, "declares 255 fields");
  check(good.substr(0, 33), "truncated in field 0 'h' shape: needs 8 bytes at offset 32, the file has 33 bytes");
  // A shape whose element count overflows 64 bits.
  b = good;
  const std::string huge = le_bytes(0x8000000000000000ull, 8);
  b.replace(32, 8, huge);
  check(b, "needs more bytes than the file's");
  EXPECT_NE(message_of(d / "absent.tensor").find("no such tensor file"), std::string::npos);
}

TEST(TensorFile, DuplicateNamesAreRefused) {
  ScratchDir d;
  write_tensor_file(d / "dup.tensor", {float32_field("a", {1}, {1.0}), float32_field("a", {1}, {2.0})});
  EXPECT_NE(message_of(d / "dup.tensor").find("field 1 'a' appears twice"), std::string::npos);
}

}  // namespace
}  // namespace icobrdf
