#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/csv.hpp"
#include "icobrdf/io/direction_csv.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::InputError;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {

// Directions come from sin/cos of exactly representable degree values; 1e-15 is a few ulps.
constexpr double kAngleTol = 1e-15;

std::string write(const TempDir& dir, const std::string& name, const std::string& content) {
  const auto path = dir.file(name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

// Expects read_direction_pairs_csv to throw an InputError whose message contains every fragment.
void expect_error(const std::string& path, std::initializer_list<const char*> fragments) {
  try {
    icobrdf::read_direction_pairs_csv(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const char* f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

TEST(DirectionCsv, ReadsDegreesWithBomCrlfCommentsAndBlankLines) {
  TempDir dir;
  const auto path = write(dir, "p.csv", "\xEF\xBB\xBFtheta_i,phi_i,theta_r,phi_r\r\n# comment\r\n\r\n90,0,0,0\r\n45, 180 ,30,-90\r\n");
  const auto p = icobrdf::read_direction_pairs_csv(path);
  ASSERT_EQ(p.wi.rows(), 2);
  // (90, 0) is the +x axis; (0, 0) the pole.
  EXPECT_NEAR(p.wi(0, 0), 1.0, kAngleTol);
  EXPECT_NEAR(p.wi(0, 2), 0.0, kAngleTol);
  EXPECT_NEAR(p.wr(0, 2), 1.0, kAngleTol);
  // (45, 180) = (-sqrt(1/2), 0, sqrt(1/2)); (30, -90) = (0, -1/2, sqrt(3)/2).
  EXPECT_NEAR(p.wi(1, 0), -std::sqrt(0.5), kAngleTol);
  EXPECT_NEAR(p.wr(1, 1), -0.5, kAngleTol);
  EXPECT_NEAR(p.wr(1, 2), std::sqrt(3.0) / 2, kAngleTol);
  EXPECT_EQ(p.lines, (std::vector<int>{4, 5}));
}

TEST(DirectionCsv, RadiansOnRequest) {
  TempDir dir;
  const auto path = write(dir, "d.csv", "theta,phi\n1.5707963267948966,3.141592653589793\n");
  const auto d = icobrdf::read_directions_csv(path, true);
  EXPECT_NEAR(d(0, 0), -1.0, kAngleTol);
  // Read as degrees the same row is a valid, different direction (1.57 degrees from the pole).
  EXPECT_GT(icobrdf::read_directions_csv(path, false)(0, 2), 0.999);
}

TEST(DirectionCsv, SignedThetaIsTheOppositeAzimuth) {
  TempDir dir;
  // (-30, 0) = (30, 180) = (-1/2, 0, sqrt(3)/2); (-90, 90) = (90, 270) = (0, -1, 0).
  const auto p = icobrdf::read_direction_pairs_csv(write(dir, "s.csv", "theta_i,phi_i,theta_r,phi_r\n-30,0,-90,90\n"));
  EXPECT_NEAR(p.wi(0, 0), -0.5, kAngleTol);
  EXPECT_NEAR(p.wi(0, 1), 0.0, kAngleTol);
  EXPECT_NEAR(p.wi(0, 2), std::sqrt(3.0) / 2, kAngleTol);
  EXPECT_NEAR(p.wr(0, 1), -1.0, kAngleTol);
  EXPECT_NEAR(p.wr(0, 2), 0.0, kAngleTol);
}

TEST(DirectionCsv, ScatmechGeometryMapsToSampleAzimuths) {
  TempDir dir;
  // Row 1: thetai 30, thetas 60, phis 0 (forward), no rotation: w_i = (30, 180) = (-1/2, 0, sqrt(3)/2),
  //        w_r = (60, 0) = (sqrt(3)/2, 0, 1/2).
  // Row 2: the same with rotation 90: azimuths 180 - 90 = 90 and 0 - 90 = -90: w_i = (0, 1/2, sqrt(3)/2),
  //        w_r = (0, -sqrt(3)/2, 1/2).
  // Row 3: signed angles: thetai -30 puts the source at azimuth 0, thetas -60 at phis 0 gives azimuth 180.
  const auto p = icobrdf::read_direction_pairs_csv(
      write(dir, "g.csv", "thetai,thetas,phis,rotation\n30,60,0,0\n30,60,0,90\n-30,-60,0,0\n"));
  const double h = std::sqrt(3.0) / 2;
  const double expect[3][6] = {{-0.5, 0, h, h, 0, 0.5}, {0, 0.5, h, 0, -h, 0.5}, {0.5, 0, h, -h, 0, 0.5}};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(p.wi(r, k), expect[r][k], kAngleTol) << r << " " << k;
      EXPECT_NEAR(p.wr(r, k), expect[r][3 + k], kAngleTol) << r << " " << k;
    }
  // Without the rotation column it is 0.
  const auto q = icobrdf::read_direction_pairs_csv(write(dir, "h.csv", "thetai,thetas,phis\n30,60,0\n"));
  EXPECT_NEAR(q.wi(0, 0), -0.5, kAngleTol);
  EXPECT_NEAR(q.wr(0, 0), h, kAngleTol);
}

TEST(DirectionCsv, ErrorsNameFileLineAndValue) {
  TempDir dir;
  expect_error(write(dir, "a.csv", ""), {"a.csv", "empty file"});
  expect_error(write(dir, "b.csv", "theta,phi\n1,2\n"), {"b.csv:1", "theta_i,phi_i,theta_r,phi_r", "theta,phi"});
  expect_error(write(dir, "c.csv", "theta_i,phi_i,theta_r,phi_r\n1,2,3\n"), {"c.csv:2", "expected 4 fields, found 3"});
  expect_error(write(dir, "d.csv", "theta_i,phi_i,theta_r,phi_r\n1,2,3,x\n"), {"d.csv:2", "phi_r", "'x'"});
  expect_error(write(dir, "e.csv", "theta_i,phi_i,theta_r,phi_r\n1,2,3,nan\n"), {"e.csv:2", "finite"});
  expect_error(write(dir, "f.csv", "theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n91,0,0,0\n"), {"f.csv:3", "theta_i", "[-90, 90]", "91"});
  expect_error(write(dir, "g.csv", "theta_i,phi_i,theta_r,phi_r\n0,0,0,0,5\n"), {"g.csv:2", "expected 4 fields, found 5"});
  expect_error(write(dir, "h.csv", "theta_i,phi_i,theta_r,phi_r\n10,0,0,0,5\n"), {"h.csv:2"});
  // A decimal comma turns one number into two fields.
  expect_error(write(dir, "i.csv", "theta_i,phi_i,theta_r,phi_r\n10,5,0,0,1,5\n"), {"i.csv:2", "found 6"});
  expect_error(dir.file("missing.csv"), {"missing.csv", "cannot open"});
}

// `--at` files in remote sensing's angles (icobrdf/io/angle_columns.hpp): raa = 0 and vza = sza is the hot spot
// (w_r = w_i); compass azimuths with vaa = saa likewise; further columns are ignored.
TEST(DirectionCsv, RemoteSensingLayouts) {
  TempDir dir;
  const auto p = icobrdf::read_direction_pairs_csv(write(dir, "rs.csv", "sza,vza,raa,brf\n30,30,0,0.2\n30,-30,0,0.1\n"));
  ASSERT_EQ(p.wi.rows(), 2);
  EXPECT_LT((p.wi.row(0) - p.wr.row(0)).norm(), kAngleTol);
  EXPECT_LT((p.wr.row(1) - Eigen::RowVector3d(-p.wi(1, 0), -p.wi(1, 1), p.wi(1, 2))).norm(), kAngleTol);  // specular
  const auto q = icobrdf::read_direction_pairs_csv(write(dir, "az.csv", "sza,saa,vza,vaa\n40,135,40,135\n"));
  EXPECT_LT((q.wi.row(0) - q.wr.row(0)).norm(), kAngleTol);
  expect_error(write(dir, "bad.csv", "zenith,vza,raa\n1,2,3\n"), {"bad.csv:1", "sza,vza,raa"});
}

}  // namespace ICOBRDF_UNITY_ID
