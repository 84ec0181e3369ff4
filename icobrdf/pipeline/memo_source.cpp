#include "icobrdf/pipeline/memo_source.hpp"

#include <cstring>

namespace icobrdf {
namespace {

// splitmix64's finalizer: a bijective mix of 64 bits.
std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Hashes of the bit patterns of a batch's rows, from two seeds.
std::pair<std::uint64_t, std::uint64_t> batch_key(const RowMatrix3d& wi, const RowMatrix3d& wr) {
  std::uint64_t a = mix(0x6d656d6f31ULL ^ static_cast<std::uint64_t>(wi.rows())), b = mix(0x6d656d6f32ULL + static_cast<std::uint64_t>(wi.rows()));
  const auto absorb = [&](const RowMatrix3d& m) {
    const double* d = m.data();
    for (Eigen::Index k = 0; k < m.size(); ++k) {
      std::uint64_t bits;
      std::memcpy(&bits, d + k, sizeof bits);
      a = mix(a ^ bits);
      b = mix(b + (bits ^ 0x9e3779b97f4a7c15ULL)) ^ a;
    }
  };
  absorb(wi);
  absorb(wr);
  return {a, b};
}

}  // namespace

Eigen::MatrixXd MemoSource::eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const {
  const Key key = batch_key(wi, wr);
  {
    std::lock_guard<std::mutex> g(lock_);
    const auto it = values_.find(key);
    if (it != values_.end()) {
      ++hits_;
      return it->second;
    }
  }
  Eigen::MatrixXd f = source_.eval(wi, wr);
  if (reciprocal_part_) f = 0.5 * (f + source_.eval(wr, wi));
  const std::size_t bytes = static_cast<std::size_t>(f.size()) * sizeof(double);
  std::lock_guard<std::mutex> g(lock_);
  ++misses_;
  if (bytes > max_bytes_ || values_.count(key)) return f;
  while (bytes_ + bytes > max_bytes_ && !order_.empty()) {
    const auto it = values_.find(order_.front());
    bytes_ -= static_cast<std::size_t>(it->second.size()) * sizeof(double);
    values_.erase(it);
    order_.pop_front();
  }
  values_.emplace(key, f);
  order_.push_back(key);
  bytes_ += bytes;
  return f;
}

long long MemoSource::hits() const {
  std::lock_guard<std::mutex> g(lock_);
  return hits_;
}

long long MemoSource::misses() const {
  std::lock_guard<std::mutex> g(lock_);
  return misses_;
}

}  // namespace icobrdf
