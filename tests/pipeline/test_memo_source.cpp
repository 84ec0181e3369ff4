// MemoSource: the values of a batch asked again are those computed the first time (bit for bit), the source
// is evaluated once per distinct batch, and the oldest batches go first when the memory bound is reached.
#include <gtest/gtest.h>

#include <atomic>

#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/pipeline/memo_source.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

// A source that counts its evaluations and reports itself slow, around an analytic model.
class CountingSource final : public BrdfSource {
 public:
  CountingSource() : inner_(open_source("model:ggx:alpha=0.2,f0=0.04")) {}
  std::string spec() const override { return inner_->spec(); }
  int channels() const override { return inner_->channels(); }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    ++evaluations;
    return inner_->eval(wi, wr);
  }
  Spectrum fit(const ProjectionContext& ctx, const FitOptions& o) const override { return inner_->fit(ctx, o); }
  bool slow_to_evaluate() const override { return true; }
  mutable std::atomic<int> evaluations{0};

 private:
  std::unique_ptr<BrdfSource> inner_;
};

TEST(MemoSource, RepeatedBatchesAreEvaluatedOnceWithTheSameValues) {
  const CountingSource src;
  const MemoSource memo(src);
  RowMatrix3d wi, wr, wi2, wr2;
  uniform_pairs(500, 11, wi, wr);
  uniform_pairs(500, 12, wi2, wr2);
  const Eigen::MatrixXd first = memo.eval(wi, wr);
  const Eigen::MatrixXd again = memo.eval(wi, wr);
  const Eigen::MatrixXd other = memo.eval(wi2, wr2);
  EXPECT_EQ(src.evaluations.load(), 2);
  EXPECT_EQ(memo.hits(), 1);
  EXPECT_EQ(memo.misses(), 2);
  EXPECT_TRUE((first.array() == again.array()).all());
  EXPECT_TRUE((first.array() == src.eval(wi, wr).array()).all());
  EXPECT_TRUE((other.array() == src.eval(wi2, wr2).array()).all());
  // One bit changed in one row is another batch.
  RowMatrix3d moved = wi;
  moved(7, 0) = std::nextafter(moved(7, 0), 2.0);
  const int before = src.evaluations.load();
  memo.eval(moved, wr);
  EXPECT_EQ(src.evaluations.load(), before + 1);
  // The wrapped source answers the questions.
  EXPECT_TRUE(memo.slow_to_evaluate());
  EXPECT_EQ(memo.spec(), src.spec());
  EXPECT_EQ(memo.channels(), src.channels());
}

TEST(MemoSource, DropsTheOldestBatchAtTheBound) {
  const CountingSource src;
  RowMatrix3d a, ar, b, br;
  uniform_pairs(100, 1, a, ar);
  uniform_pairs(100, 2, b, br);
  // Room for one batch of 100 pairs x 1 channel (800 bytes), not two.
  const MemoSource memo(src, 100 * sizeof(double) * static_cast<size_t>(src.channels()) + 8);
  memo.eval(a, ar);
  memo.eval(b, br);  // drops a
  memo.eval(b, br);  // kept
  memo.eval(a, ar);  // evaluated again
  EXPECT_EQ(memo.hits(), 1);
  EXPECT_EQ(memo.misses(), 3);
  EXPECT_EQ(src.evaluations.load(), 3);
}

}  // namespace ICOBRDF_UNITY_ID

namespace ICOBRDF_UNITY_ID {

// f = a + b (cos theta_i - cos theta_r): its reciprocal part is a, its antisymmetric part b (cos_i - cos_r).
class AntisymmetricSource final : public BrdfSource {
 public:
  static constexpr double kA = 0.3, kB = 0.1;
  std::string spec() const override { return "test:antisymmetric"; }
  int channels() const override { return 1; }
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const override {
    return (Eigen::ArrayXd::Constant(wi.rows(), kA) + kB * (wi.col(2).array() - wr.col(2).array())).matrix();
  }
  Spectrum fit(const ProjectionContext&, const FitOptions&) const override { throw std::logic_error("not used"); }
};

// Rounding of a sum of two doubles halved.
constexpr double kHalfSumRounding = 1e-15;

TEST(MemoSource, TheReciprocalPartIsTheMeanOfBothOrderings) {
  const AntisymmetricSource src;
  const MemoSource memo(src, MemoSource::ReciprocalPart{});
  RowMatrix3d wi, wr;
  uniform_pairs(300, 5, wi, wr);
  const Eigen::MatrixXd f = memo.eval(wi, wr);
  EXPECT_LT((f.array() - AntisymmetricSource::kA).abs().maxCoeff(), kHalfSumRounding);
  EXPECT_TRUE((memo.eval(wr, wi).array() == f.array()).all()) << "exchanging the directions changes nothing";
  EXPECT_GT((src.eval(wi, wr).array() - AntisymmetricSource::kA).abs().maxCoeff(), 0.01) << "the source itself is not reciprocal";
}

}  // namespace ICOBRDF_UNITY_ID
