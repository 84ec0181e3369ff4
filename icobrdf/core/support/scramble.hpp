#pragma once
// splitmix64's finalizer (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA
// 2014): a fixed, platform-independent bijection of 64-bit integers whose every output bit depends on every
// input bit. Used to deal samples into folds and held-out sets by their index: consecutive indices land
// far apart, so files in scan order are not split into runs of neighbouring measurements.
#include <cstdint>
#include <string>

namespace icobrdf {

inline std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// FNV-1a, 64 bits, of a text: the seeds of draws named by text (a material's held-out pairs are seeded by
// "holdout|" + its name), the same on every platform.
inline std::uint64_t fnv1a64(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

}  // namespace icobrdf
