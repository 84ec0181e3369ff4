// Compiled once per SIMD target (Highway foreach_target); see icobrdf/core/support/simd_target.hpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "icobrdf/core/support/simd_target.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>

#include "icobrdf/core/support/simd_target.hpp"

HWY_BEFORE_NAMESPACE();
namespace icobrdf {
namespace HWY_NAMESPACE {

std::int64_t TargetBits() { return HWY_TARGET; }
int F64Lanes() { return static_cast<int>(hwy::HWY_NAMESPACE::Lanes(hwy::HWY_NAMESPACE::ScalableTag<double>())); }

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

HWY_EXPORT(TargetBits);
HWY_EXPORT(F64Lanes);

namespace {
// The targets this CPU runs, read before any ScopedSimdTarget narrows what Highway reports.
std::int64_t cpu_targets() {
  static const std::int64_t targets = hwy::SupportedTargets();
  return targets;
}

SimdTarget target_of(std::int64_t bits) {
  SimdTarget t;
  t.bits = bits;
  t.name = hwy::TargetName(bits);
  t.runs_here = (cpu_targets() & bits) != 0;
  return t;
}
}  // namespace

std::vector<SimdTarget> compiled_simd_targets() {
  std::vector<SimdTarget> out;
  // Lower bits are better targets on every architecture Highway knows.
  for (std::int64_t left = HWY_TARGETS; left != 0; left &= left - 1) out.push_back(target_of(left & -left));
  return out;
}

SimdTarget dispatched_simd_target() { return target_of(HWY_DYNAMIC_DISPATCH(TargetBits)()); }

int dispatched_f64_lanes() { return HWY_DYNAMIC_DISPATCH(F64Lanes)(); }

ScopedSimdTarget::ScopedSimdTarget(const SimdTarget& target) {
  if ((cpu_targets() & target.bits) == 0)
    throw UnsupportedError("SIMD target " + target.name + " does not run on this CPU");
  hwy::SetSupportedTargetsForTest(target.bits);
}

ScopedSimdTarget::~ScopedSimdTarget() { hwy::SetSupportedTargetsForTest(0); }

}  // namespace icobrdf
#endif
