#include "icobrdf/pipeline/level_order_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "icobrdf/core/support/error.hpp"

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
  void see(double l2, int level, int order) {
    if (!(l2 < error)) return;
    error = l2;
    where = "level " + std::to_string(level) + " order " + std::to_string(order);
  }
};

// The smallest order n in [first, top] of `level` whose own fit meets the target. With `all` (the fit at top)
// the errors of its truncations choose the orders worth fitting; without it (refit_each_order) every order is
// fitted, and an order whose fit is refused (UnsupportedError) is skipped.
std::optional<LevelOrderChoice> first_order_meeting(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts,
                                                    const HeldOutErrors& errors, double target, int level, int first, int top,
                                                    const Spectrum* all, BestSoFar& best) {
  for (int n = first; n <= top; ++n) {
    if (all) {
      const double l2 = errors(truncate_channels(all->channels, n), n).l2;
      best.see(l2, level, n);
      if (search.seen) search.seen(level, n, l2);
      if (l2 > target) continue;
    }
    LevelOrderChoice c;
    try {
      c.spectrum = all && n == top ? *all : fit_source(source, at(search, level, n), contexts).spectrum;
    } catch (const UnsupportedError& e) {
      if (all) throw;
      if (best.where.empty()) best.where = "order " + std::to_string(n) + " (its fit refused: " + e.what() + ")";
      continue;
    }
    c.error = errors(c.spectrum.channels, n);
    if (!all) best.see(c.error.l2, level, n);
    if (!all && search.seen) search.seen(level, n, c.error.l2);
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
  const int lowest = search.fixed_order >= 0 ? search.fixed_order : 0;
  int tried = -1;  // refit_each_order: orders up to this one were fitted on an earlier level
  for (int level : search.levels) {
    const int top = top_order(search, contexts, level, max_order);
    if (top < 0) continue;
    std::optional<Spectrum> all;
    if (!search.refit_each_order) all = fit_source(source, at(search, level, top), contexts).spectrum;
    const int first = search.refit_each_order ? std::max(tried + 1, lowest) : lowest;
    auto choice = first_order_meeting(source, search, contexts, errors, target, level, first, top, all ? &*all : nullptr, best);
    tried = std::max(tried, top);
    if (choice) accept(*choice);
    say(name + ": level " + std::to_string(level) + " up to order " + std::to_string(top) + (all ? "" : " (each order fitted)") +
        (choice ? ": target met" : ": target not met"));
    if (choice) return std::move(*choice);
  }
  char buf[1024];
  std::snprintf(buf, sizeof buf, "target %.3g not met: best relative L2 error %.3g at %s (order_max %d, levels tried up to %d)", target,
                best.error, best.where.c_str(), search.order_max, search.levels.back());
  throw UnsupportedError(buf);
}

void each_level_order(const BrdfSource& source, const LevelOrderSearch& search, FitContexts& contexts,
                      const std::function<void(int level, const Spectrum& spectrum)>& see) {
  const int max_order = search.fixed_order >= 0 ? search.fixed_order : search.order_max;
  const int lowest = search.fixed_order >= 0 ? search.fixed_order : 0;
  for (int level : search.levels) {
    const int top = top_order(search, contexts, level, max_order);
    if (top < 0) continue;
    if (!search.refit_each_order) {
      const Spectrum all = fit_source(source, at(search, level, top), contexts).spectrum;
      for (int n = lowest; n <= top; ++n) {
        Spectrum s = all;
        s.channels = truncate_channels(all.channels, n);
        s.order = n;
        see(level, s);
      }
      continue;
    }
    for (int n = lowest; n <= top; ++n) {
      try {
        see(level, fit_source(source, at(search, level, n), contexts).spectrum);
      } catch (const UnsupportedError&) {  // an order the samples cannot bound
      }
    }
  }
}

}  // namespace icobrdf
