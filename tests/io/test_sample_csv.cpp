// BRDF samples CSV (icobrdf/io/sample_csv.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/sample_csv.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ScratchDir;

// direction_from_angles of degrees converted to radians: a few ulps.
constexpr double kDirTol = 1e-15;

std::string error_of(const std::string& file, const SampleCsvOptions& o = {}) {
  try {
    read_sample_csv(file, o);
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos);
    return m;
  }
  ADD_FAILURE() << "no InputError for " << file;
  return "";
}

TEST(SampleCsv, ReadsDegreesOneAndThreeChannels) {
  ScratchDir d;
  test::write_bytes(d / "a.csv", "theta_i,phi_i,theta_r,phi_r,value\n30,0,45,180,0.25\n0,10,90,-90,1.5\n");
  const BrdfSamples s = read_sample_csv(d / "a.csv");
  ASSERT_EQ(s.wi.rows(), 2);
  EXPECT_EQ(s.channels, 1);
  EXPECT_LT((s.wi.row(0).transpose() - direction_from_angles(M_PI / 6, 0)).norm(), kDirTol);
  EXPECT_LT((s.wr.row(0).transpose() - direction_from_angles(M_PI / 4, M_PI)).norm(), kDirTol);
  EXPECT_LT((s.wr.row(1).transpose() - direction_from_angles(M_PI / 2, -M_PI / 2)).norm(), kDirTol);
  EXPECT_EQ(s.values(1, 0), 1.5);
  EXPECT_EQ(s.lines[1], 3);
  EXPECT_EQ(s.weights.sum(), 2.0);
  EXPECT_TRUE(s.plane_of_incidence);  // (0 -> 180) and a pole direction

  // BOM, CRLF, comments, three channels, radians.
  test::write_bytes(d / "b.csv", "\xEF\xBB\xBFtheta_i,phi_i,theta_r,phi_r,r,g,b\r\n# comment\r\n0.5,0.1,1.0,2.0,1,2,3\r\n");
  SampleCsvOptions o;
  o.radians = true;
  const BrdfSamples t = read_sample_csv(d / "b.csv", o);
  EXPECT_EQ(t.channels, 3);
  EXPECT_EQ(t.values(0, 2), 3.0);
  EXPECT_LT((t.wr.row(0).transpose() - direction_from_angles(1.0, 2.0)).norm(), kDirTol);
  EXPECT_FALSE(t.plane_of_incidence);
}

// Policy: duplicates (same pair, phi reduced mod 360) are averaged with weight = count.
TEST(SampleCsv, DuplicatesAreAveragedAndCounted) {
  ScratchDir d;
  test::write_bytes(d / "dup.csv",
                    "theta_i,phi_i,theta_r,phi_r,value\n10,20,30,40,1\n10,-340,30,-320,3\n10,20,30,40,5\n0,5,30,40,7\n0,99,30,40,9\n");
  const BrdfSamples s = read_sample_csv(d / "dup.csv");
  ASSERT_EQ(s.wi.rows(), 2);  // (10,20,30,40) x3 and the pole pair x2 (phi irrelevant at theta = 0)
  EXPECT_EQ(s.duplicates_merged, 3);
  EXPECT_EQ(s.rows, 5);
  EXPECT_DOUBLE_EQ(s.values(0, 0), 3.0);  // (1 + 3 + 5)/3
  EXPECT_EQ(s.weights[0], 3.0);
  EXPECT_DOUBLE_EQ(s.values(1, 0), 8.0);
  EXPECT_EQ(s.weights[1], 2.0);
}

TEST(SampleCsv, NonReciprocalPairsReportedOrRefusedWhenStrict) {
  ScratchDir d;
  test::write_bytes(d / "r.csv",
                    "theta_i,phi_i,theta_r,phi_r,value\n10,20,30,40,1\n30,40,10,20,1.5\n50,0,60,0,2\n60,0,50,0,2\n");
  const BrdfSamples s = read_sample_csv(d / "r.csv");
  EXPECT_EQ(s.reciprocal_pairs, 2);
  EXPECT_EQ(s.nonreciprocal_pairs, 1);
  EXPECT_DOUBLE_EQ(s.max_reciprocity_difference, 0.5 / 1.5);
  SampleCsvOptions o;
  o.strict = true;
  const std::string m = error_of(d / "r.csv", o);
  EXPECT_NE(m.find(":2: sample and its reciprocal at line 3 differ by 0.3333333333 (relative), expected at most 1e-06 (--strict)"),
            std::string::npos) << m;
}

TEST(SampleCsv, BadInputIsLineNumbered) {
  ScratchDir d;
  auto check = [&](const std::string& name, const std::string& content, const std::string& expect) {
    test::write_bytes(d / name, content);
    const std::string m = error_of(d / name);
    EXPECT_NE(m.find(expect), std::string::npos) << m << "\n  lacks: " << expect;
    EXPECT_EQ(m.rfind(d / name, 0), 0u) << m;
  };
  const std::string h = "theta_i,phi_i,theta_r,phi_r,value\n";
  check("empty.csv", "", "empty file, expected a header row");
  check("nodata.csv", h, "no samples after the header");
  check("theta.csv", h + "10,0,95,0,1\n", ":2: column 'theta_r' expected a polar angle in [-90, 90] degrees, found 95");
  check("thneg.csv", h + "1,0,5,0,1\n-91,0,5,0,1\n", ":3: column 'theta_i' expected a polar angle in [-90, 90] degrees, found -91");
  check("phi.csv", h + "10,400,5,0,1\n", ":2: column 'phi_i' expected an azimuth in [-360, 360], found 400");
  check("nan.csv", h + "10,0,5,0,nan\n", ":2: column 'value' expected a");
  check("inf.csv", h + "10,0,5,0,inf\n", ":2: column 'value' expected a");
  check("comma.csv", h + "10,0,5,0,0,5\n", ":2: expected 5 fields, found 6");
  check("fields.csv", h + "10,0,5\n", ":2: expected 5 fields, found 3");
  check("text.csv", h + "10,0,5,x,1\n", ":2: column 'phi_r' expected a number, found 'x'");
  check("cols.csv", "theta_i,phi_i,theta_r,phi_r,a,b\n1,2,3,4,5,6\n", ":1: expected 5 columns (theta_i,phi_i,theta_r,phi_r,value) or 7");
  check("header.csv", "theta_r,phi_r,theta_i,phi_i,value\n1,2,3,4,5\n", ":1: expected header starting");
  SampleCsvOptions rad;
  rad.radians = true;
  test::write_bytes(d / "rad.csv", h + "1.6,0,0.5,0,1\n");
  const std::string m = error_of(d / "rad.csv", rad);
  EXPECT_NE(m.find(":2: column 'theta_i' expected a polar angle in [-pi/2, pi/2] radians (declared by the option 'radians'), found 1.6"),
            std::string::npos) << m;
}

// NIST writes in-plane geometries with a signed theta (PTFE.data.csv: thetai = -45, phi = 0 puts the source at
// azimuth 180 deg; /work/data's ptfe_eval.py reproduces Germer's fit only so): a negative theta is the direction
// (|theta|, phi + 180). A signed row and the same geometry written unsigned are one sample (merged, weight 2).
TEST(SampleCsv, SignedThetaIsTheDirectionAtPhiPlus180) {
  ScratchDir d;
  test::write_bytes(d / "s.csv", "theta_i,phi_i,theta_r,phi_r,f\n-45,0,30,0,1\n45,180,30,0,3\n20,10,-60,-80,5\n");
  const BrdfSamples s = read_sample_csv(d / "s.csv");
  ASSERT_EQ(s.wi.rows(), 2);
  EXPECT_EQ(s.signed_theta_rows, 2);
  EXPECT_EQ(s.duplicates_merged, 1);
  EXPECT_EQ(s.weights[0], 2.0);
  EXPECT_DOUBLE_EQ(s.values(0, 0), 2.0);
  EXPECT_LT((s.wi.row(0).transpose() - direction_from_angles(M_PI / 4, M_PI)).norm(), kDirTol);
  EXPECT_LT((s.wr.row(1).transpose() - direction_from_angles(M_PI / 3, M_PI * 100.0 / 180.0)).norm(), kDirTol);
  EXPECT_FALSE(s.plane_of_incidence);  // the second sample's azimuths differ by 90 deg
}

// The unit declared by the option, the column names or a '# units:' line gives the same samples; declarations
// that disagree, radians left undeclared (every angle within radian ranges: a fit reaching |f| ~ 1e9) and
// degrees declared as radians are refused in one line naming the likely mistake.
TEST(SampleCsv, DeclaredUnitsAndUnitMistakes) {
  ScratchDir d;
  const std::string rows = "0.5,0.1,1.0,2.0,1\n0.2,3.0,0.7,-1.0,2\n";
  SampleCsvOptions rad;
  rad.radians = true;
  test::write_bytes(d / "opt.csv", "theta_i,phi_i,theta_r,phi_r,f\n" + rows);
  test::write_bytes(d / "cols.csv", "theta_i_rad,phi_i_rad,theta_r_rad,phi_r_rad,f\n" + rows);
  test::write_bytes(d / "line.csv", "# measured somewhere\n# Units: Radians\ntheta_i,phi_i,theta_r,phi_r,f\n" + rows);
  const BrdfSamples a = read_sample_csv(d / "opt.csv", rad), b = read_sample_csv(d / "cols.csv"), c = read_sample_csv(d / "line.csv");
  EXPECT_LT((a.wr.row(0).transpose() - direction_from_angles(1.0, 2.0)).norm(), kDirTol);
  EXPECT_EQ(b.wi, a.wi);
  EXPECT_EQ(b.wr, a.wr);
  EXPECT_EQ(c.wi, a.wi);
  EXPECT_TRUE(b.radians && c.radians);
  EXPECT_NE(c.unit_declared_by.find("line 2"), std::string::npos) << c.unit_declared_by;

  const std::string und = error_of(d / "opt.csv");
  EXPECT_NE(und.find("these look like radians read as degrees"), std::string::npos) << und;
  EXPECT_NE(und.find("# units: radians"), std::string::npos) << und;
  // Declared degrees are taken at their word.
  test::write_bytes(d / "deg.csv", "theta_i_deg,phi_i_deg,theta_r_deg,phi_r_deg,f\n" + rows);
  EXPECT_FALSE(read_sample_csv(d / "deg.csv").radians);

  const std::string clash = error_of(d / "deg.csv", rad);
  EXPECT_NE(clash.find("the column names (_deg) declares degrees but the option 'radians' declares radians"), std::string::npos) << clash;
  test::write_bytes(d / "mixed.csv", "theta_i_rad,phi_i_rad,theta_r_deg,phi_r_deg,f\n" + rows);
  EXPECT_NE(error_of(d / "mixed.csv").find("2 '_deg' and 2 '_rad' suffixes"), std::string::npos);
  test::write_bytes(d / "word.csv", "# units: grad\ntheta_i,phi_i,theta_r,phi_r,f\n" + rows);
  EXPECT_NE(error_of(d / "word.csv").find("word.csv:1: units line expected 'degrees' or 'radians', found 'grad'"), std::string::npos);

  test::write_bytes(d / "degs.csv", "theta_i,phi_i,theta_r,phi_r,f\n30,0,45,180,1\n60,90,10,270,2\n");
  const std::string m = error_of(d / "degs.csv", rad);
  EXPECT_NE(m.find(":2: column 'theta_i' expected a polar angle in [-pi/2, pi/2] radians (declared by the option 'radians'); "
                   "the file's angles look like degrees, found 30"),
            std::string::npos) << m;
}

// Remote-sensing layouts (icobrdf/io/angle_columns.hpp): sza,vza,raa puts the sun at azimuth 0 and the viewer at
// raa, so raa = 0 and vza = sza is the hot spot (the viewer along the sun's rays, w_r = w_i) and raa = 180 the
// forward (specular) side; BRF columns are divided by pi; a signed vza is the opposite azimuth.
TEST(SampleCsv, RemoteSensingRelativeAzimuthLayout) {
  ScratchDir d;
  test::write_bytes(d / "rs.csv", "sza,vza,raa,brf\n30,30,0,0.5\n30,30,180,0.2\n40,-20,0,0.3\n");
  const BrdfSamples s = read_sample_csv(d / "rs.csv");
  ASSERT_EQ(s.wi.rows(), 3);
  EXPECT_EQ(s.layout, AngleLayout::SunViewRelative);
  EXPECT_EQ(s.quantity, ValueQuantity::Brf);
  EXPECT_LT((s.wi.row(0) - s.wr.row(0)).norm(), kDirTol);  // the hot spot
  const Eigen::Vector3d mirror(-s.wi(1, 0), -s.wi(1, 1), s.wi(1, 2));
  EXPECT_LT((s.wr.row(1).transpose() - mirror).norm(), kDirTol);  // raa = 180, vza = sza: the specular direction
  EXPECT_LT((s.wr.row(2).transpose() - direction_from_angles(M_PI / 9, M_PI)).norm(), kDirTol);
  EXPECT_DOUBLE_EQ(s.values(0, 0), 0.5 / M_PI);
  EXPECT_EQ(s.signed_theta_rows, 1);
  // BRDF values are taken as they are; so are those the option declares.
  test::write_bytes(d / "f.csv", "sza,vza,raa,brdf\n30,30,0,0.5\n");
  EXPECT_DOUBLE_EQ(read_sample_csv(d / "f.csv").values(0, 0), 0.5);
  test::write_bytes(d / "nir.csv", "sza,vza,raa,nir\n30,30,0,0.5\n");
  SampleCsvOptions brf;
  brf.columns.values = "brf";
  EXPECT_DOUBLE_EQ(read_sample_csv(d / "nir.csv", brf).values(0, 0), 0.5 / M_PI);
}

// sza,saa,vza,vaa: compass azimuths of the sun and the sensor seen from the surface; vaa = saa is the sun's side
// whatever saa, and only the difference matters for an isotropic surface's geometry (w_i . w_r).
TEST(SampleCsv, RemoteSensingAzimuthLayout) {
  ScratchDir d;
  test::write_bytes(d / "az.csv", "sza_rad,saa_rad,vza_rad,vaa_rad,brf\n0.5,1.0,0.5,1.0,0.4\n0.5,4.0,0.3,4.7,0.4\n");
  const BrdfSamples s = read_sample_csv(d / "az.csv");
  EXPECT_TRUE(s.radians);
  EXPECT_EQ(s.layout, AngleLayout::SunViewAzimuths);
  EXPECT_LT((s.wi.row(0) - s.wr.row(0)).norm(), kDirTol);
  // Phase angle from the remote-sensing formula with raa = vaa - saa.
  const double cos_xi = std::cos(0.5) * std::cos(0.3) + std::sin(0.5) * std::sin(0.3) * std::cos(4.7 - 4.0);
  EXPECT_NEAR(s.wi.row(1).dot(s.wr.row(1)), cos_xi, kDirTol * 4);
  // Compass north (azimuth 0) is +y, east (90) is +x.
  test::write_bytes(d / "n.csv", "sza,saa,vza,vaa,brf\n90,0,90,90,0.4\n");
  const BrdfSamples n = read_sample_csv(d / "n.csv");
  EXPECT_LT((n.wi.row(0).transpose() - Eigen::Vector3d(0, 1, 0)).norm(), kDirTol);
  EXPECT_LT((n.wr.row(0).transpose() - Eigen::Vector3d(1, 0, 0)).norm(), kDirTol);
}

// Unknown value names in a remote-sensing layout, mixed quantities, a header of no layout and columns= of the
// wrong count are refused in one line; columns= renames the header.
TEST(SampleCsv, RemoteSensingColumnErrorsAndRenaming) {
  ScratchDir d;
  test::write_bytes(d / "nir.csv", "sza,vza,raa,nir\n30,30,0,0.5\n");
  EXPECT_NE(error_of(d / "nir.csv").find("nir.csv:1: value column 'nir' does not say its quantity"), std::string::npos);
  test::write_bytes(d / "mix.csv", "sza,vza,raa,brf_red,brdf_nir,brf_blue\n30,30,0,0.5,0.1,0.2\n");
  EXPECT_NE(error_of(d / "mix.csv").find("expected one quantity for every value column"), std::string::npos);
  test::write_bytes(d / "other.csv", "solar_zenith,view_zenith,rel_az,brf\n30,30,0,0.5\n");
  EXPECT_NE(error_of(d / "other.csv").find("'sza,vza,raa'"), std::string::npos);
  SampleCsvOptions renamed;
  renamed.columns.names = {"sza", "vza", "raa", "brf"};
  EXPECT_DOUBLE_EQ(read_sample_csv(d / "other.csv", renamed).values(0, 0), 0.5 / M_PI);
  renamed.columns.names = {"sza", "vza", "raa"};
  EXPECT_NE(error_of(d / "other.csv", renamed).find("the option columns= names 3 columns"), std::string::npos);
  test::write_bytes(d / "range.csv", "sza,vza,raa,brf\n30,95,0,0.5\n");
  EXPECT_NE(error_of(d / "range.csv").find("range.csv:2: column 'vza' expected a polar angle in [-90, 90] degrees, found 95"),
            std::string::npos) << error_of(d / "range.csv");
}

}  // namespace
}  // namespace icobrdf
