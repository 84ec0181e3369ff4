#include "icobrdf/io/sample_draws.hpp"

#include <fmt/core.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ostream>
#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/io/disk_space.hpp"

namespace icobrdf {
namespace {

// The next `n` draws from `rng`: u1 then u2 of each draw in turn; weighed (f evaluated) or not.
MaterialSamples draw_block(const MaterialSampler& sampler, const IncidentDistribution& dist, long long n, std::mt19937_64& rng,
                           bool weighed = true) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::VectorXd u1(n), u2(n);
  for (long long i = 0; i < n; ++i) u1[i] = uniform(rng), u2[i] = uniform(rng);
  return weighed ? sampler.sample(dist, u1, u2) : sampler.draw(dist, u1, u2);
}

// The checked weights of every block, kept between the two passes in an unnamed temporary file of $TMPDIR
// (or /tmp): 8 bytes per draw and channel, removed by the system when closed, whatever ends the process.
// The folder's free space is checked against all of them first (ResourceError, before any draw).
class WeightSpool {
 public:
  WeightSpool(std::string what, long long draws, int channels) : what_(std::move(what)) {
    const char* dir = std::getenv("TMPDIR");
    dir_ = dir && *dir ? dir : "/tmp";
    require_disk_space(static_cast<double>(sizeof(double)) * static_cast<double>(draws) * channels, dir_,
                       fmt::format("{}: the temporary file of the checked weights ({} draws x {} channel(s))", what_, draws, channels),
                       "nothing was written; set TMPDIR to a folder with 8 bytes per draw and channel free");
    std::string name = dir_ + "/icobrdf-sample-XXXXXX";
    const int fd = ::mkstemp(name.data());
    if (fd < 0) fail("cannot be created");
    ::unlink(name.c_str());
    file_ = ::fdopen(fd, "w+b");
    if (!file_) {
      ::close(fd);
      fail("cannot be opened");
    }
  }
  WeightSpool(const WeightSpool&) = delete;
  WeightSpool& operator=(const WeightSpool&) = delete;
  ~WeightSpool() {
    if (file_) std::fclose(file_);
  }
  void put(const Eigen::MatrixXd& w) {
    const auto count = static_cast<std::size_t>(w.size());
    if (count > 0 && std::fwrite(w.data(), sizeof(double), count, file_) != count) fail("cannot be written");
  }
  void rewind() {
    if (std::fflush(file_) != 0 || std::fseek(file_, 0, SEEK_SET) != 0) fail("cannot be written");
  }
  void get(Eigen::MatrixXd& w) {
    const auto count = static_cast<std::size_t>(w.size());
    if (count > 0 && std::fread(w.data(), sizeof(double), count, file_) != count) fail("cannot be read back");
  }

 private:
  [[noreturn]] void fail(const std::string& what_failed) const {
    const int e = errno;
    throw IoError(fmt::format("{}: the temporary file that keeps the checked weights between the two passes, in {}, {} ({}); "
                              "nothing was written; set TMPDIR to a folder with 8 bytes per draw and channel free",
                              what_, dir_, what_failed, e ? std::strerror(e) : "end of file"));
  }
  std::string what_, dir_;
  std::FILE* file_ = nullptr;
};

std::string samples_csv_header(const MaterialSampler& sampler) {
  std::string text = "theta_r,phi_r,pdf";
  for (const std::string& c : channel_column_names(sampler.source())) text += ",weight" + c.substr(1);  // "f_r" -> "weight_r"
  return text + "\n";
}

std::string samples_csv_rows(const MaterialSamples& s) {
  std::string text;
  for (Eigen::Index i = 0; i < s.directions.rows(); ++i) {
    const Angles a = angles_from_direction(s.directions.row(i).transpose());
    text += fmt::format("{},{},{}", a.theta * 180 / M_PI, a.phi * 180 / M_PI, s.pdf[i]);
    for (Eigen::Index c = 0; c < s.weight.cols(); ++c) text += fmt::format(",{}", s.weight(i, c));
    text += "\n";
  }
  return text;
}

// UnsupportedError naming the first draw (counted from 0 over the whole run) whose weight is not finite.
void require_finite_weights(const MaterialSampler& sampler, const MaterialSamples& s, long long first) {
  for (Eigen::Index i = 0; i < s.weight.rows(); ++i)
    for (Eigen::Index c = 0; c < s.weight.cols(); ++c)
      if (!std::isfinite(s.weight(i, c)))
        throw UnsupportedError(fmt::format("{}: the weight of draw {} is {} (f at the drawn direction is not finite); nothing was written",
                                           sampler.source().spec(), first + i, s.weight(i, c)));
}

}  // namespace

bool write_material_samples_csv(std::ostream& out, const MaterialSampler& sampler, const Eigen::Vector3d& wi, long long n,
                                std::uint64_t seed) {
  const IncidentDistribution dist = sampler.distribution(wi);
  if (n <= kSampleDrawBlock) {  // one block: drawn and checked once
    std::mt19937_64 rng(seed);
    const MaterialSamples s = draw_block(sampler, dist, n, rng);
    require_finite_weights(sampler, s, 0);
    out << samples_csv_header(sampler) << samples_csv_rows(s);
    return static_cast<bool>(out);
  }
  // Several blocks: each is drawn and weighed once, its weights checked and kept in the spool; then the
  // directions are drawn again from the same seed (no f evaluated) and written with the kept weights.
  const long long blocks = (n + kSampleDrawBlock - 1) / kSampleDrawBlock;
  WeightSpool spool(sampler.source().spec(), n, sampler.source().channels());
  {
    ProgressMeter progress("drawing", blocks);
    std::mt19937_64 rng(seed);
    for (long long first = 0; first < n; first += kSampleDrawBlock) {
      const MaterialSamples s = draw_block(sampler, dist, std::min(kSampleDrawBlock, n - first), rng);
      require_finite_weights(sampler, s, first);
      spool.put(s.weight);
      progress.step();
    }
  }
  spool.rewind();
  ProgressMeter progress("writing", blocks);
  std::mt19937_64 rng(seed);
  out << samples_csv_header(sampler);
  for (long long first = 0; first < n && out; first += kSampleDrawBlock) {
    MaterialSamples s = draw_block(sampler, dist, std::min(kSampleDrawBlock, n - first), rng, false);
    s.weight.resize(s.directions.rows(), sampler.source().channels());
    spool.get(s.weight);
    out << samples_csv_rows(s);
    progress.step();
  }
  return static_cast<bool>(out);
}

}  // namespace icobrdf
