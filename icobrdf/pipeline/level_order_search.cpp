#include "icobrdf/pipeline/level_order_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "icobrdf/core/error.hpp"

namespace icobrdf {
namespace {

FitRequest at(const LevelOrderSearch& search, int level, int order) {
  FitRequest r = search.base;
  r.level = level;
  r.order = order;
  return r;
}

// The largest order fitted at `level` (-1: the level cannot take the search's orders).
int top_order(const LevelOrderSearch& search, FitContexts& contexts, int level, int cap) {
  const int top = std::min(cap, contexts.supported_order(at(search, level, search.order_max)));
  return top < 0 || (search.fixed_order >= 0 && top < search.fixed_order) ? -1 : top;
}

// The smallest truncation error seen, for the message when no (level, order) meets the target.
struct BestSoFar {
  double error = INFINITY;
  std::string where;
};

// The smallest order n in [first, top] of `level` whose own fit meets the target; `all` (the fit at top)
// gives the errors of the truncations.
std::optional<LevelOrderChoice> first_order_meeting(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts,
                                                    const HeldOutErrors& errors, double target, int level, int top, const Spectrum& all,
                                                    BestSoFar& best) {
  const int first = search.fixed_order >= 0 ? search.fixed_order : 0;
  for (int n = first; n <= top; ++n) {
    const double l2 = errors(truncate_channels(all.channels, n), n).l2;
    if (l2 < best.error) {
      best.error = l2;
      best.where = "level " + std::to_string(level) + " order " + std::to_string(n);
    }
    if (l2 > target) continue;
    LevelOrderChoice c;
    c.spectrum = n == top ? all : fit_source(source, at(search, level, n), contexts).spectrum;
    c.error = errors(c.spectrum.channels, n);
    if (c.error.l2 > target) continue;
    c.level = level;
    c.order = n;
    c.top = top;
    return c;
  }
  return std::nullopt;
}

}  // namespace

LevelOrderChoice fit_at_given_order(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts) {
  for (int level : search.levels) {
    const int top = top_order(search, contexts, level, search.order_max);
    if (top < 0) continue;
    LevelOrderChoice c;
    c.level = level;
    c.order = c.top = search.fixed_order >= 0 ? search.fixed_order : top;
    c.spectrum = fit_source(source, at(search, level, c.order), contexts).spectrum;
    c.error = {std::nan(""), std::nan("")};
    return c;
  }
  throw UnsupportedError("order " + std::to_string(search.fixed_order) + " is not supported by any of the levels tried (up to " +
                         std::to_string(search.levels.back()) + ")");
}

LevelOrderChoice search_level_order(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts,
                                    const HeldOutErrors& errors, double target, const std::string& name,
                                    const std::function<void(LevelOrderChoice&)>& accept,
                                    const std::function<void(const std::string&)>& say) {
  const int max_order = search.fixed_order >= 0 ? search.fixed_order : search.order_max;
  BestSoFar best;
  for (int level : search.levels) {
    const int top = top_order(search, contexts, level, max_order);
    if (top < 0) continue;
    const Spectrum all = fit_source(source, at(search, level, top), contexts).spectrum;
    auto choice = first_order_meeting(source, search, contexts, errors, target, level, top, all, best);
    if (choice) accept(*choice);
    say(name + ": level " + std::to_string(level) + " up to order " + std::to_string(top) + (choice ? ": target met" : ": target not met"));
    if (choice) return std::move(*choice);
  }
  char buf[256];
  std::snprintf(buf, sizeof buf, "target %.3g not met: best relative L2 error %.3g at %s (order_max %d, levels tried up to %d)", target,
                best.error, best.where.c_str(), search.order_max, search.levels.back());
  throw UnsupportedError(buf);
}

}  // namespace icobrdf
