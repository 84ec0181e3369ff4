// The CURET reader (icobrdf/io/curet.hpp) on the public database files (tests/data/measured) and on broken
// copies of them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/curet.hpp"
#include "io_test_support.hpp"
#include "measured_fixtures.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::measured_fixture;
using test::ScratchDir;

// direction_from_angles of the table's radians: a few ulps.
constexpr double kDirTol = 1e-15;

std::string slurp_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string curet_error(const std::string& brdf, const std::string& table) {
  try {
    read_curet(brdf, table);
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

// Layout and values as the files print them (tests/data/measured/README.md; /work/data/README.md section 3).
TEST(Curet, ReadsThePublicDatabase) {
  const CuretDatabase db = read_curet(measured_fixture("abrdf.dat"), measured_fixture("table.txt"));
  ASSERT_EQ(db.wi.rows(), 205);
  ASSERT_EQ(db.values.rows(), 61);
  EXPECT_EQ(db.sample_numbers.front(), 1);
  EXPECT_EQ(db.sample_numbers.back(), 61);
  // table.txt line 2: "2     0.981748    0.000000   1.374447    0.000000" (theta_v, phi_v, theta_i, phi_i).
  EXPECT_LT((db.wr.row(1).transpose() - direction_from_angles(0.981748, 0.0)).norm(), kDirTol);
  EXPECT_LT((db.wi.row(1).transpose() - direction_from_angles(1.374447, 0.0)).norm(), kDirTol);
  // line 1: "1     1.389566   -1.970402   1.374447   -1.570796".
  EXPECT_LT((db.wi.row(0).transpose() - direction_from_angles(1.374447, -1.570796)).norm(), kDirTol);
  // abrdf.dat line 1 begins "1    0.200   0.110   0.199".
  EXPECT_EQ(db.values(0, 0), 0.200);
  EXPECT_EQ(db.values(0, 2), 0.199);
  // The 29 reciprocal geometry pairs listed in /work/data/README.md, e.g. rows (2, 20) and (190, 200).
  ASSERT_EQ(db.reciprocal_pairs.size(), 29u);
  EXPECT_EQ(db.reciprocal_pairs.front(), std::make_pair(1, 19));
  EXPECT_EQ(db.reciprocal_pairs.back(), std::make_pair(189, 199));
  // 29 negative values, all in samples 4 and 61.
  long long negative = 0;
  for (int n = 1; n <= 61; ++n) {
    const BrdfSamples s = curet_samples(db, n);
    negative += s.negative_values;
    if (n != 4 && n != 61) {
      EXPECT_EQ(s.negative_values, 0) << n;
    }
  }
  EXPECT_EQ(negative, 29);
  const BrdfSamples s12 = curet_samples(db, 12);
  EXPECT_EQ(s12.values(0, 0), db.values(11, 0));
  EXPECT_EQ(s12.reciprocal_pairs, 29);
  EXPECT_FALSE(s12.plane_of_incidence);
  EXPECT_EQ(curet_table_beside(measured_fixture("abrdf.dat")), measured_fixture("table.txt"));
  try {
    curet_samples(db, 62);
    ADD_FAILURE() << "sample 62 accepted";
  } catch (const ArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("no sample 62, expected one of 1..61"), std::string::npos) << e.what();
  }
}

TEST(Curet, BrokenFilesAreRefusedWithFileAndLine) {
  ScratchDir d;
  const std::string table = slurp_file(measured_fixture("table.txt")), brdf = slurp_file(measured_fixture("abrdf.dat"));
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(d / name, std::ios::binary) << text;
    return d / name;
  };
  const std::string good_table = write("table.txt", table), good_brdf = write("abrdf.dat", brdf);
  // The table in degrees: line 1's theta_v 1.389566 rad = 79.6 deg.
  std::string deg = table;
  deg.replace(deg.find("1.389566"), 8, "79.61604");
  EXPECT_NE(curet_error(good_brdf, write("deg.txt", deg)).find("deg.txt:1: theta_v expected a polar angle in [0, pi/2] radians, found 79.61604 (degrees?"),
            std::string::npos);
  std::string four = table;
  four.replace(four.find("0.981748    0.000000"), 20, "0.981748");
  EXPECT_NE(curet_error(good_brdf, write("four.txt", four)).find("four.txt:2: expected 5 fields"), std::string::npos);
  // A sample line one value short.
  std::string short_line = brdf;
  short_line.replace(short_line.find("0.200"), 5, "");
  EXPECT_NE(curet_error(write("short.dat", short_line), good_table).find("short.dat:1: expected 206 fields"), std::string::npos);
  std::string text = brdf;
  text.replace(text.find("0.110"), 5, "x.110");
  EXPECT_NE(curet_error(write("text.dat", text), good_table).find("text.dat:1: field 3 expected a finite number, found 'x.110'"),
            std::string::npos);
  EXPECT_NE(curet_error(write("twice.dat", brdf + brdf), good_table).find("twice.dat:62: sample 1 repeats line 1"), std::string::npos);
}

}  // namespace
}  // namespace icobrdf
