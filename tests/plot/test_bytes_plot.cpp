// Error against bytes of a bank material's candidates, checked by content: one curve per representation along
// its lower envelope, every point drawn in its representation's colour, the stored candidate as a black
// diamond, and no picture for a material without candidates.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/plot/bytes_plot.hpp"
#include "icobrdf/plot/figure.hpp"
#include "tests/plot/plot_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::plot {
namespace ICOBRDF_UNITY_ID {

using test::TempDir;
using test::byte_distance;

// A filled marker's centre pixel against its colour: antialiasing reaches only its rim.
constexpr int kMarkerBytes = 3;

TEST(PlotBytes, LowerEnvelopeKeepsThePointsNoSmallerOneBeats) {
  const std::vector<CandidatePoint> pts{{"modes", 100, 0.5}, {"modes", 60, 0.4}, {"modes", 200, 0.45}, {"modes", 300, 0.1}, {"modes", 300, 0.2}};
  const auto env = lower_envelope(pts);
  ASSERT_EQ(env.size(), 2u);  // 60 bytes at 0.4, then 300 bytes at 0.1: 100 and 200 bytes do no better than 60
  EXPECT_EQ(env[0].bytes, 60);
  EXPECT_EQ(env[1].bytes, 300);
  EXPECT_EQ(env[1].error_l2, 0.1);
}

TEST(PlotBytes, PointsCurvesTargetAndTheStoredCandidate) {
  BankMaterialCandidates m;
  m.name = "glossy";
  m.target = 0.02;
  m.points = {{"modes", 60, 0.9}, {"modes", 600, 0.3}, {"modes", 6000, 0.05}, {"half-angle", 17000, 0.01}, {"half-angle", 2000, 0.06}};
  m.chosen = {"half-angle", 17000, 0.01};
  TempDir d;
  const BytesFigure f = plot_bytes("bank.h5#glossy", m, d.file("b.png"));
  EXPECT_EQ(f.points, 5);
  ASSERT_EQ(f.representations, (std::vector<std::string>{"half-angle", "modes"}));  // in name order: colours 0 and 1
  const PngImage img = read_png(d.file("b.png"));
  // The modes' points not under the stored diamond, in their colour (palette index 1).
  for (const auto& p : {m.points[0], m.points[1], m.points[2]})
    EXPECT_LE(byte_distance(img.at(static_cast<int>(f.frame.px(p.bytes)), static_cast<int>(f.frame.py(p.error_l2))), series_colour(1)),
              kMarkerBytes)
        << p.bytes;
  EXPECT_LE(byte_distance(img.at(static_cast<int>(f.frame.px(2000)), static_cast<int>(f.frame.py(0.06))), series_colour(0)), kMarkerBytes);
  // The stored candidate: black.
  EXPECT_LE(byte_distance(img.at(static_cast<int>(f.frame.px(17000)), static_cast<int>(f.frame.py(0.01))), {0.0, 0.0, 0.0}), kMarkerBytes);
  // Log-log axes spanning whole decades around the points.
  EXPECT_TRUE(f.frame.log_x && f.frame.log_y);
  EXPECT_LE(f.frame.x0, 30.0);
  EXPECT_GE(f.frame.x1, 34000.0);
  m.points.clear();
  EXPECT_THROW(plot_bytes("old.h5#glossy", m, d.file("old.png")), InputError);
  EXPECT_NE(access(d.file("old.png").c_str(), F_OK), 0);
}

}  // namespace
}  // namespace icobrdf::plot
