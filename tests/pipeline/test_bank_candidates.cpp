// The `candidates` label of a bank material: an exact round trip of every point, duplicates merged to the lowest
// error, and one-line refusals of a newer version or a malformed entry.
#include <gtest/gtest.h>

#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/pipeline/bank_candidates.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

TEST(BankCandidates, TextRoundTripsExactlyAndMergesDuplicates) {
  const std::vector<CandidatePoint> pts{{"modes", 120, 0.1 / 3}, {"half-angle", 16933, 0.004620000000000001}, {"modes", 60, 0.5},
                                        {"modes", 120, 0.2}};
  const std::string t = candidates_text(pts);
  EXPECT_EQ(t.rfind("icobrdf-candidates 1; representation,bytes,error_l2; ", 0), 0u) << t;
  const auto back = parse_candidates(t, "test");
  ASSERT_EQ(back.size(), 3u);  // modes at 120 bytes once, with its lower error
  EXPECT_EQ(back[0].representation, "half-angle");
  EXPECT_EQ(back[0].error_l2, 0.004620000000000001);  // 17 significant digits: the same double
  EXPECT_EQ(back[1].bytes, 60);
  EXPECT_EQ(back[2].bytes, 120);
  EXPECT_EQ(back[2].error_l2, 0.1 / 3);
  EXPECT_TRUE(parse_candidates(candidates_text({}), "test").empty());
}

TEST(BankCandidates, RefusesNewerVersionsAndMalformedEntries) {
  for (const std::string bad : {"icobrdf-candidates 2; representation,bytes,error_l2; modes,60,0.5",
                                "icobrdf-candidates 1; representation,bytes,error_l2; modes,0,0.5",
                                "icobrdf-candidates 1; representation,bytes,error_l2; modes,60,nan",
                                "icobrdf-candidates 1; representation,bytes; modes,60", "something else"}) {
    try {
      parse_candidates(bad, "bank.h5 material 'm'");
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      const std::string w = e.what();
      EXPECT_EQ(w.find('\n'), std::string::npos) << w;
      EXPECT_EQ(w.rfind("bank.h5 material 'm'", 0), 0u) << w;
    }
  }
}

}  // namespace
}  // namespace icobrdf
