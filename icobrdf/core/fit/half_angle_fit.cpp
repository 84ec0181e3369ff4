#include "icobrdf/core/fit/half_angle_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/basis/half_angle.hpp"
#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/serial_eigen.hpp"

namespace icobrdf {

PairSampler model_pair_sampler(const BrdfModel& model) {
  return [&model](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    model.eval(wi, wr, out);
  };
}

void uniform_pairs(int n, std::uint64_t seed, RowMatrix3d& wi, RowMatrix3d& wr) {
  std::mt19937_64 rng(seed);
  wi.resize(n, 3);
  wr.resize(n, 3);
  for (int k = 0; k < n; ++k) {
    wi.row(k) = uniform_direction(rng).transpose();
    wr.row(k) = uniform_direction(rng).transpose();
  }
}

namespace {

// Weighted ALS for one channel: minimizes sum W (Q - U V^T)^2 with W = 0 at missing nodes.
struct AlsProblem {
  const Eigen::MatrixXd& W;   // H x D, fitting weights (valid nodes and weighted extension)
  const Eigen::MatrixXd& WQ;  // W .* Q
  const Eigen::MatrixXd& Wv;  // weights of the valid nodes only (the error measure)
  double norm2;               // sum Wv Q^2
};

// sum Wv (Q - U V^T)^2 (the error) and sum W (Q - U V^T)^2 (the objective).
std::pair<double, double> weighted_error2(const AlsProblem& p, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& U,
                                          const Eigen::MatrixXd& V) {
  Eigen::MatrixXd E = Q;
  if (U.cols() > 0) E.noalias() -= U * V.transpose();
  E = E.array().square();
  return {(p.Wv.array() * E.array()).sum(), (p.W.array() * E.array()).sum()};
}

// The pair products Y_r Y_s (r <= s) of the columns of Y, weighted by the rows of Wt: n x R(R+1)/2.
template <class WMat>
Eigen::MatrixXd pair_products(const WMat& Wt, const Eigen::MatrixXd& Y) {
  const int R = static_cast<int>(Y.cols());
  Eigen::MatrixXd YY(Y.rows(), R * (R + 1) / 2);
  for (int r = 0, p = 0; r < R; ++r)
    for (int s = r; s < R; ++s, ++p) YY.col(p) = Y.col(r).cwiseProduct(Y.col(s));
  return Wt * YY;
}

// Rows X solving (unpack(A_i) .* G + ridge) X_i = B_i for every i: A is n x R(R+1)/2 (pair_products), B is
// n x R, G is R x R (all ones for one channel; S^T S for shared factors with channel scales S).
Eigen::MatrixXd solve_rows(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& G) {
  const int R = static_cast<int>(B.cols());
  Eigen::MatrixXd X(A.rows(), R);
  // Serial: each row is an R x R solve (~0.1-1 us); a parallel region here cost 25x the whole fit on a loaded
  // 2-core machine (threads waiting at the barrier behind other processes), and the products above thread.
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxFitRank, kMaxFitRank>;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    Small N(R, R);
    for (int r = 0, p = 0; r < R; ++r)
      for (int s = r; s < R; ++s, ++p) N(r, s) = N(s, r) = A(i, p) * G(r, s);
    const double tr = N.trace();
    if (!(tr > 0.0)) {
      X.row(i).setZero();
      continue;
    }
    N.diagonal().array() += 1e-14 * tr;
    X.row(i) = N.ldlt().solve(B.row(i).transpose()).transpose();
  }
  return X;
}

// New rows X (n x R) minimizing sum_j Wt(i, j) (T(i, j) - X_i . Y_j)^2 for every i, given Y (m x R).
// Wt is W or W^T, WT = Wt .* T.
template <class WMat, class WQMat>
Eigen::MatrixXd solve_side(const WMat& Wt, const WQMat& WT, const Eigen::MatrixXd& Y) {
  const Eigen::MatrixXd G = Eigen::MatrixXd::Ones(Y.cols(), Y.cols());
  return solve_rows(pair_products(Wt, Y), WT * Y, G);
}

// Leading singular pair of the weighted residual sqrt(a_i b_j) M_ij (Q - U V^T)_ij by power iteration,
// returned as sqrt(sigma) l and sqrt(sigma) r.
void leading_residual_term(const AlsProblem& p, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& U,
                           const Eigen::MatrixXd& V, Eigen::VectorXd& u, Eigen::VectorXd& v) {
  Eigen::MatrixXd S = Q;
  if (U.cols() > 0) S.noalias() -= U * V.transpose();
  S.array() *= p.W.array().sqrt();
  Eigen::VectorXd r = Eigen::VectorXd::Ones(S.cols()), l;
  double sigma = 0.0;
  for (int it = 0; it < 300; ++it) {
    l = S * r;
    const double ln = l.norm();
    if (!(ln > 0.0)) break;
    l /= ln;
    r = S.transpose() * l;
    const double s = r.norm();
    if (!(s > 0.0)) break;
    r /= s;
    const bool done = std::abs(s - sigma) <= 1e-10 * s;
    sigma = s;
    if (done) break;
  }
  u = Eigen::VectorXd::Zero(S.rows());
  v = Eigen::VectorXd::Zero(S.cols());
  if (!(sigma > 0.0)) return;
  // Still in weighted scale: the caller divides by sqrt(a) and sqrt(b).
  u = std::sqrt(sigma) * l;
  v = std::sqrt(sigma) * r;
}

struct ChannelFit {
  Eigen::MatrixXd U, V;  // H x R, D x R
  std::vector<double> error_by_rank;
  std::vector<int> sweeps;
  bool zero = false;
};

int als_sweeps(const AlsProblem& p, const Eigen::MatrixXd& Q, Eigen::MatrixXd& U, Eigen::MatrixXd& V,
               const HalfAngleFitOptions& o, double& e2) {
  double obj = weighted_error2(p, Q, U, V).second;
  int sweep = 0;
  for (; sweep < o.max_sweeps; ++sweep) {
    U = solve_side(p.W, p.WQ, V);
    V = solve_side(p.W.transpose(), p.WQ.transpose(), U);
    const auto [err2, obj2] = weighted_error2(p, Q, U, V);
    const bool stalled = obj - obj2 <= o.sweep_tolerance * obj;
    obj = obj2;
    e2 = err2;
    if (stalled || obj <= 1e-30 * p.norm2) {
      ++sweep;
      break;
    }
  }
  return sweep;
}

// Orders the terms by weighted energy: U V^T = (U') (V')^T with diag(sqrt a) U' and diag(sqrt b) V'
// orthogonal columns scaled by sqrt(sigma); returns sigma.
Eigen::VectorXd orthogonalize(Eigen::MatrixXd& U, Eigen::MatrixXd& V, const Eigen::VectorXd& a,
                              const Eigen::VectorXd& b) {
  const int R = static_cast<int>(U.cols());
  if (R == 0) return {};
  const Eigen::VectorXd sa = a.array().sqrt(), sb = b.array().sqrt();
  const Eigen::MatrixXd Ua = sa.asDiagonal() * U, Vb = sb.asDiagonal() * V;
  Eigen::HouseholderQR<Eigen::MatrixXd> qu(Ua), qv(Vb);
  const Eigen::MatrixXd Q1 = qu.householderQ() * Eigen::MatrixXd::Identity(U.rows(), R);
  const Eigen::MatrixXd Q2 = qv.householderQ() * Eigen::MatrixXd::Identity(V.rows(), R);
  const Eigen::MatrixXd R1 = qu.matrixQR().topRows(R).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd R2 = qv.matrixQR().topRows(R).triangularView<Eigen::Upper>();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R1 * R2.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd sig = svd.singularValues();
  const Eigen::VectorXd root = sig.array().sqrt();
  U = sa.cwiseInverse().asDiagonal() * (Q1 * svd.matrixU() * root.asDiagonal());
  V = sb.cwiseInverse().asDiagonal() * (Q2 * svd.matrixV() * root.asDiagonal());
  return sig;
}

}  // namespace

namespace {

void check_fit_options(int channels, const HalfAngleFitOptions& o) {
  const auto bad = [](const std::string& what) { throw ArgumentError("half-angle fit: " + what); };
  if (channels < 1) bad("channels = " + std::to_string(channels) + ", expected >= 1");
  if (o.n_t < 2 || o.n_theta_d < 2 || o.n_phi_d < 1 || (!o.isotropic && o.n_phi_h < 1))
    bad("grid sizes n_t = " + std::to_string(o.n_t) + ", n_phi_h = " + std::to_string(o.n_phi_h) +
        ", n_theta_d = " + std::to_string(o.n_theta_d) + ", n_phi_d = " + std::to_string(o.n_phi_d) +
        ", expected n_t, n_theta_d >= 2 and n_phi_h, n_phi_d >= 1");
  if (!(o.h_warp >= 0.25 && o.h_warp <= 8.0)) bad("h_warp outside [0.25, 8]");
  if (!o.isotropic && !(std::abs(o.h_axis) <= M_PI && o.h_scale_1 >= kMinHScale && o.h_scale_1 <= kMaxHScale &&
                        o.h_scale_2 >= kMinHScale && o.h_scale_2 <= kMaxHScale))
    bad("h stretch outside h_axis in [-pi, pi], scales in [" + std::to_string(kMinHScale) + ", " + std::to_string(kMaxHScale) + "]");
  if (!(o.target > 0.0)) bad("target must be > 0");
  if (o.max_rank < 1 || o.fixed_rank < 0 || o.max_rank > kMaxFitRank || o.fixed_rank > kMaxFitRank)
    bad("max_rank must be in [1, " + std::to_string(kMaxFitRank) + "] and fixed_rank in [0, " + std::to_string(kMaxFitRank) + "]");
}

// The node values q, the fitting weights W (valid nodes, and the extension at a small weight) and the error
// weights Wv (valid nodes only) of a fit.
struct SampledNodes {
  std::vector<Eigen::MatrixXd> Q;  // per channel, H x D
  Eigen::MatrixXd W, Wv;           // H x D
  long long missing = 0;           // valid node pairs left out as missing data
};

// Samples q at the valid node pairs (weight a_h b_d), then at the missing nodes that share an interpolation
// cell with a valid one (weight extension_weight a_h b_d, extended values).
SampledNodes sample_nodes(const PairSampler& sampler, int channels, const HalfAngleFitOptions& o, const HalfAngleFactors& F,
                          const Eigen::VectorXd& a, const Eigen::VectorXd& b, double* valid_fraction) {
  const int H = F.h_nodes(), D = F.d_nodes();
  SampledNodes out{std::vector<Eigen::MatrixXd>(channels, Eigen::MatrixXd::Zero(H, D)), Eigen::MatrixXd::Zero(H, D),
                   Eigen::MatrixXd::Zero(H, D)};
  std::vector<Eigen::MatrixXd>& Q = out.Q;
  Eigen::MatrixXd &W = out.W, &Wv = out.Wv;
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> valid(H, D);
  const HalfAngleNodeTrig ht = half_angle_h_trig(F), dt = half_angle_d_trig(F);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < D; ++j) valid(i, j) = node_pair_valid(ht, i, dt, j);
  *valid_fraction = valid.cast<double>().mean();
  const auto near_valid = [&](int i, int j) {
    const int k = i / F.n_phi_h, jh = i % F.n_phi_h, ad = j / F.n_phi_d, bd = j % F.n_phi_d;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = (F.n_phi_h > 1 ? -1 : 0); dj <= (F.n_phi_h > 1 ? 1 : 0); ++dj)
        for (int da = -1; da <= 1; ++da)
          for (int db = (F.n_phi_d > 1 ? -1 : 0); db <= (F.n_phi_d > 1 ? 1 : 0); ++db) {
            const int k2 = k + dk, a2 = ad + da;
            if (k2 < 0 || k2 >= F.n_t || a2 < 0 || a2 >= F.n_theta_d) continue;
            const int j2 = (jh + dj + F.n_phi_h) % F.n_phi_h, b2 = (bd + db + F.n_phi_d) % F.n_phi_d;
            if (valid(k2 * F.n_phi_h + j2, a2 * F.n_phi_d + b2)) return true;
          }
    return false;
  };
  // Extension across the horizon: f at the directions pushed onto the horizon (z -> 0, renormalized),
  // times the signed cosines for the cosine quantity; q is then C^1 across the boundary where f is
  // continuous, so that interpolation cells straddling it stay second-order accurate.
  const auto to_horizon = [](Eigen::Vector3d& w) {
    if (w.z() >= 0.0) return true;
    const double r = std::hypot(w.x(), w.y());
    if (!(r > 1e-3)) return false;
    w = Eigen::Vector3d(w.x() / r, w.y() / r, 0.0);
    return true;
  };
  const bool extend = o.extension_weight > 0.0;
  const int block = std::max(1, (1 << 16) / D);
  for (int h0 = 0; h0 < H; h0 += block) {
    const int h1 = std::min(H, h0 + block);
    std::vector<std::pair<int, int>> nodes;
    std::vector<double> cosines, metric_factor;
    RowMatrix3d wi((h1 - h0) * D, 3), wr((h1 - h0) * D, 3);
    for (int i = h0; i < h1; ++i)
      for (int j = 0; j < D; ++j) {
        if (!valid(i, j) && !(extend && near_valid(i, j))) continue;
        Eigen::Vector3d x, y;
        half_angle_node_pair(F, i, j, x, y);
        const double cc = o.quantity == HalfAngleQuantity::MeanCosine ? 0.5 * (x.z() + y.z()) : x.z() * y.z();
        if (valid(i, j)) {
          x.z() = std::max(x.z(), 0.0);
          y.z() = std::max(y.z(), 0.0);
        } else if (!to_horizon(x) || !to_horizon(y)) {
          continue;
        }
        wi.row(nodes.size()) = x.transpose();
        wr.row(nodes.size()) = y.transpose();
        nodes.emplace_back(i, j);
        const double ci = std::max(x.z(), 0.0), cr = std::max(y.z(), 0.0);
        cosines.push_back(!valid(i, j) ? cc : o.quantity == HalfAngleQuantity::MeanCosine ? 0.5 * (ci + cr) : ci * cr);
        // Mean-cosine: the metric's q = f ci cr is the stored p times H = 2 ci cr / (ci + cr).
        metric_factor.push_back(o.quantity != HalfAngleQuantity::MeanCosine || !valid(i, j) ? 1.0
                                : ci + cr > 0.0                                             ? 2.0 * ci * cr / (ci + cr)
                                                                                            : 0.0);
      }
    const auto n = static_cast<Eigen::Index>(nodes.size());
    if (n == 0) continue;
    const RowMatrix3d wiv = wi.topRows(n), wrv = wr.topRows(n);
    Eigen::MatrixXd f(n, channels);
    sampler(wiv, wrv, f);
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto [i, j] = nodes[k];
      const double cc = o.quantity != HalfAngleQuantity::F ? cosines[k] : 1.0;
      if (o.skip_missing && !(f.row(k).array() * cc).allFinite()) {  // missing data: a gap, like the horizon
        out.missing += valid(i, j) ? 1 : 0;
        continue;
      }
      for (int c = 0; c < channels; ++c) {
        const double q = f(k, c) * cc;
        if (!std::isfinite(q)) {
          std::ostringstream s;
          s << "the sampled f of channel " << c << " is not finite (" << f(k, c) << ") at w_i = (" << wiv.row(k)
            << "), w_r = (" << wrv.row(k) << ")";
          throw ArgumentError("half-angle fit: " + s.str());
        }
        Q[c](i, j) = q;
      }
      const double m2 = metric_factor[k] * metric_factor[k];
      W(i, j) = a(i) * b(j) * (valid(i, j) ? m2 : o.extension_weight);
      if (valid(i, j)) Wv(i, j) = a(i) * b(j) * m2;
    }
  }

  return out;
}

// Rank by rank, every channel that still misses the target gets one more term; returns the rank reached.
// `after_rank(rank)` is called after every rank (false: stop there).
int grow_ranks(const SampledNodes& n, const HalfAngleFitOptions& o, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
               std::vector<ChannelFit>& cf, std::vector<double>& norm2, std::vector<double>& e2, std::vector<int>& sweeps_by_rank,
               const std::function<bool(int)>& after_rank) {
  const int channels = static_cast<int>(n.Q.size());
  const Eigen::Index H = n.W.rows(), D = n.W.cols();
  const std::vector<Eigen::MatrixXd>& Q = n.Q;
  const Eigen::MatrixXd &W = n.W, &Wv = n.Wv;
  const int max_rank = o.fixed_rank > 0 ? o.fixed_rank : o.max_rank;
  const double target2 = o.fixed_rank > 0 ? -1.0 : o.target * o.target;
  cf.assign(channels, ChannelFit{});
  std::vector<Eigen::MatrixXd> WQ(channels);
  norm2.assign(channels, 0.0);
  e2.assign(channels, 0.0);
  for (int c = 0; c < channels; ++c) {
    WQ[c] = W.cwiseProduct(Q[c]);
    norm2[c] = Wv.cwiseProduct(Q[c]).cwiseProduct(Q[c]).sum();
    cf[c].U.resize(H, 0);
    cf[c].V.resize(D, 0);
    cf[c].zero = !(norm2[c] > 0.0);
    e2[c] = cf[c].zero ? 0.0 : norm2[c];
  }
  const Eigen::VectorXd sa = a.array().sqrt(), sb = b.array().sqrt();
  int rank = 0;
  for (int r = 1; r <= max_rank; ++r) {
    bool any = false;
    int sweeps = 0;
    for (int c = 0; c < channels; ++c) {
      if (cf[c].zero || e2[c] <= target2 * norm2[c]) continue;
      any = true;
      const AlsProblem p{W, WQ[c], Wv, norm2[c]};
      Eigen::VectorXd un, vn;
      leading_residual_term(p, Q[c], cf[c].U, cf[c].V, un, vn);
      // The residual was scaled by sqrt(W) = sqrt(a_i b_j) on valid nodes: unscale the singular vectors.
      un = un.cwiseQuotient(sa);
      vn = vn.cwiseQuotient(sb);
      Eigen::MatrixXd U(H, r), V(D, r);
      U << cf[c].U, un;
      V << cf[c].V, vn;
      const int s = als_sweeps(p, Q[c], U, V, o, e2[c]);
      sweeps = std::max(sweeps, s);
      cf[c].U = std::move(U);
      cf[c].V = std::move(V);
      cf[c].error_by_rank.push_back(std::sqrt(e2[c] / norm2[c]));
    }
    if (!any) break;
    rank = r;
    sweeps_by_rank.push_back(sweeps);
    if (after_rank && !after_rank(rank)) break;
  }

  return rank;
}

// Shared factors (HalfAngleFactors::channel_scales): q_c = U diag(S_c) V^T for every channel c, fitted by
// alternating least squares over U, S and V (a weighted CP decomposition of the node values over (h, d,
// channel)).
struct SharedFit {
  Eigen::MatrixXd U, V, S;                         // H x R, D x R, C x R
  std::vector<std::vector<double>> error_by_rank;  // [channel][r - 1]
  std::vector<int> sweeps_by_rank;
};

// Channel scales minimizing the weighted error for given U, V: per channel M s_c = b_c with
// M(r, s) = sum_i A(i, rs) U(i, r) U(i, s) (A = pair_products(W, V)) and b_c = column sums of U .* (WQ_c V).
Eigen::MatrixXd solve_scales(const Eigen::MatrixXd& A, const std::vector<Eigen::MatrixXd>& B, const Eigen::MatrixXd& U) {
  const int R = static_cast<int>(U.cols());
  Eigen::MatrixXd M(R, R);
  for (int r = 0, p = 0; r < R; ++r)
    for (int q = r; q < R; ++q, ++p) M(r, q) = M(q, r) = A.col(p).dot(U.col(r).cwiseProduct(U.col(q)));
  const double tr = M.trace();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(B.size()), R);
  if (!(tr > 0.0)) return S;
  M.diagonal().array() += 1e-14 * tr;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
  for (size_t c = 0; c < B.size(); ++c)
    S.row(static_cast<Eigen::Index>(c)) = ldlt.solve(U.cwiseProduct(B[c]).colwise().sum().transpose()).transpose();
  return S;
}

// Error (valid nodes) and objective (fitting weights) per channel of the shared factors.
void shared_errors(const SampledNodes& n, const std::vector<Eigen::MatrixXd>& WQ, const std::vector<double>& norm2, const SharedFit& f,
                   std::vector<double>& e2, double& objective) {
  objective = 0.0;
  for (size_t c = 0; c < n.Q.size(); ++c) {
    const AlsProblem p{n.W, WQ[c], n.Wv, norm2[c]};
    const auto [err2, obj2] = weighted_error2(p, n.Q[c], f.U * f.S.row(static_cast<Eigen::Index>(c)).asDiagonal(), f.V);
    e2[c] = err2;
    objective += obj2;
  }
}

// One sweep: U, then S, then V; columns of U and V rescaled to unit norm (their sizes go into S).
void shared_sweep(const SampledNodes& n, const std::vector<Eigen::MatrixXd>& WQ, SharedFit& f) {
  const size_t C = n.Q.size();
  std::vector<Eigen::MatrixXd> B(C);
  const Eigen::MatrixXd A = pair_products(n.W, f.V);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(f.U.rows(), f.U.cols());
  for (size_t c = 0; c < C; ++c) {
    B[c] = WQ[c] * f.V;
    rhs += B[c] * f.S.row(static_cast<Eigen::Index>(c)).asDiagonal();
  }
  f.U = solve_rows(A, rhs, f.S.transpose() * f.S);
  f.S = solve_scales(A, B, f.U);
  const Eigen::MatrixXd At = pair_products(n.W.transpose(), f.U);
  Eigen::MatrixXd rhs_v = Eigen::MatrixXd::Zero(f.V.rows(), f.V.cols());
  for (size_t c = 0; c < C; ++c) rhs_v += (WQ[c].transpose() * f.U) * f.S.row(static_cast<Eigen::Index>(c)).asDiagonal();
  f.V = solve_rows(At, rhs_v, f.S.transpose() * f.S);
  for (Eigen::Index r = 0; r < f.U.cols(); ++r) {
    const double nu = f.U.col(r).norm(), nv = f.V.col(r).norm();
    if (!(nu > 0.0 && nv > 0.0)) continue;
    f.U.col(r) /= nu;
    f.V.col(r) /= nv;
    f.S.col(r) *= nu * nv;
  }
}

// Rank by rank until every channel meets the target (or the fixed rank): each new term starts from the
// leading singular pair of the weighted residual summed over the channels, its scales by least squares.
// `after_rank(f)` is called after every rank (false: stop there).
SharedFit grow_shared(const SampledNodes& n, const HalfAngleFitOptions& o, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                      std::vector<double>& norm2, std::vector<double>& e2, const std::function<bool(const SharedFit&)>& after_rank) {
  const size_t C = n.Q.size();
  const int max_rank = o.fixed_rank > 0 ? o.fixed_rank : o.max_rank;
  const double target2 = o.fixed_rank > 0 ? -1.0 : o.target * o.target;
  std::vector<Eigen::MatrixXd> WQ(C);
  norm2.assign(C, 0.0);
  e2.assign(C, 0.0);
  SharedFit f;
  f.U.resize(n.W.rows(), 0);
  f.V.resize(n.W.cols(), 0);
  f.S.resize(static_cast<Eigen::Index>(C), 0);
  f.error_by_rank.resize(C);
  for (size_t c = 0; c < C; ++c) {
    WQ[c] = n.W.cwiseProduct(n.Q[c]);
    norm2[c] = n.Wv.cwiseProduct(n.Q[c]).cwiseProduct(n.Q[c]).sum();
    e2[c] = norm2[c];
  }
  const Eigen::VectorXd sa = a.array().sqrt(), sb = b.array().sqrt();
  const auto meets = [&] {
    for (size_t c = 0; c < C; ++c)
      if (norm2[c] > 0.0 && e2[c] > target2 * norm2[c]) return false;
    return true;
  };
  for (int r = 1; r <= max_rank && !meets(); ++r) {
    Eigen::MatrixXd residual = Eigen::MatrixXd::Zero(n.W.rows(), n.W.cols());
    for (size_t c = 0; c < C; ++c) {
      residual += n.Q[c];
      // Rank 0 has no terms yet; a row of the 0-column S would be a block of a null pointer.
      if (f.U.cols() > 0) residual -= f.U * f.S.row(static_cast<Eigen::Index>(c)).asDiagonal() * f.V.transpose();
    }
    const AlsProblem p{n.W, n.W, n.Wv, 0.0};
    Eigen::VectorXd un, vn;
    leading_residual_term(p, residual, Eigen::MatrixXd(n.W.rows(), 0), Eigen::MatrixXd(n.W.cols(), 0), un, vn);
    Eigen::MatrixXd U(n.W.rows(), r), V(n.W.cols(), r);
    U << f.U, un.cwiseQuotient(sa);
    V << f.V, vn.cwiseQuotient(sb);
    f.U = std::move(U);
    f.V = std::move(V);
    f.S = solve_scales(pair_products(n.W, f.V), [&] {
      std::vector<Eigen::MatrixXd> B(C);
      for (size_t c = 0; c < C; ++c) B[c] = WQ[c] * f.V;
      return B;
    }(), f.U);
    double obj;
    shared_errors(n, WQ, norm2, f, e2, obj);
    int sweep = 0;
    for (; sweep < o.max_sweeps; ++sweep) {
      shared_sweep(n, WQ, f);
      double obj2;
      shared_errors(n, WQ, norm2, f, e2, obj2);
      const bool stalled = obj - obj2 <= o.sweep_tolerance * obj;
      obj = obj2;
      if (stalled || !(obj > 1e-30)) {
        ++sweep;
        break;
      }
    }
    f.sweeps_by_rank.push_back(sweep);
    for (size_t c = 0; c < C; ++c) f.error_by_rank[c].push_back(norm2[c] > 0.0 ? std::sqrt(e2[c] / norm2[c]) : 0.0);
    if (after_rank && !after_rank(f)) break;
  }
  return f;
}

// A fit as returned: factors at the options' precision, the time so far.
void finish_fit(const HalfAngleFitOptions& o, std::chrono::steady_clock::time_point t0, HalfAngleFit& fit) {
  fit.factors.precision = o.precision;
  fit.factors.quantize();
  fit.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The shared ALS state into fit.factors (one factor set, channel scales) and its report; returns the worst
// channel's node error.
double shared_result(const SharedFit& sf, const std::vector<double>& norm2, const std::vector<double>& e2, const Eigen::VectorXd& a,
                     const Eigen::VectorXd& b, HalfAngleFit& fit) {
  const int rank = static_cast<int>(sf.U.cols()), channels = static_cast<int>(norm2.size());
  HalfAngleFactors& F = fit.factors;
  F.rank = fit.report.rank = rank;
  fit.report.sweeps_by_rank = sf.sweeps_by_rank;
  fit.report.error_by_rank = sf.error_by_rank;
  fit.report.energies.assign(channels, {});
  double worst = 0.0;
  for (int c = 0; c < channels; ++c) {
    const double e = norm2[c] > 0.0 ? std::sqrt(e2[c] / norm2[c]) : 0.0;
    fit.report.error.push_back(e);
    worst = std::max(worst, e);
    // Weighted norm of each term of the channel, relative to the channel's.
    for (int r = 0; r < rank; ++r)
      fit.report.energies[c].push_back(
          norm2[c] > 0.0 ? std::abs(sf.S(c, r)) * std::sqrt(a.dot(sf.U.col(r).cwiseAbs2()) * b.dot(sf.V.col(r).cwiseAbs2()) / norm2[c]) : 0.0);
  }
  F.u.emplace_back(sf.U);
  F.v.emplace_back(sf.V);
  F.channel_scales = sf.S;
  return worst;
}

// The shared fit into fit.factors and its report (options.on_rank called with each rank's); returns the worst
// channel's node error.
double store_shared(const SampledNodes& nodes, const HalfAngleFitOptions& o, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                    std::chrono::steady_clock::time_point t0, HalfAngleFit& fit) {
  std::vector<double> norm2, e2;
  std::function<bool(const SharedFit&)> after_rank;
  if (o.on_rank)
    after_rank = [&](const SharedFit& now) {
      HalfAngleFit at = fit;  // the grids, factors not yet set
      shared_result(now, norm2, e2, a, b, at);
      finish_fit(o, t0, at);
      return o.on_rank(at);
    };
  const SharedFit sf = grow_shared(nodes, o, a, b, norm2, e2, after_rank);
  return shared_result(sf, norm2, e2, a, b, fit);
}

// The per-channel ALS state at `rank` into fit.factors (terms ordered by weighted energy) and its report;
// returns the worst channel's node error.
double separate_result(const std::vector<ChannelFit>& cf, const std::vector<double>& norm2, const std::vector<double>& e2, int rank,
                       const Eigen::VectorXd& a, const Eigen::VectorXd& b, HalfAngleFit& fit) {
  const int channels = static_cast<int>(cf.size());
  const Eigen::Index H = a.size(), D = b.size();
  HalfAngleFactors& F = fit.factors;
  F.rank = rank;
  fit.report.rank = rank;
  fit.report.error.resize(channels);
  fit.report.error_by_rank.resize(channels);
  fit.report.energies.resize(channels);
  double worst = 0.0;
  for (int c = 0; c < channels; ++c) {
    Eigen::MatrixXd U = Eigen::MatrixXd::Zero(H, rank), V = Eigen::MatrixXd::Zero(D, rank);
    U.leftCols(cf[c].U.cols()) = cf[c].U;
    V.leftCols(cf[c].V.cols()) = cf[c].V;
    const Eigen::VectorXd sig = orthogonalize(U, V, a, b);
    const double e = cf[c].zero ? 0.0 : std::sqrt(e2[c] / norm2[c]);
    fit.report.error[c] = e;
    fit.report.error_by_rank[c] = cf[c].error_by_rank;
    for (int k = 0; k < sig.size(); ++k)
      fit.report.energies[c].push_back(cf[c].zero ? 0.0 : sig(k) / std::sqrt(norm2[c]));
    worst = std::max(worst, e);
    F.u.emplace_back(U);
    F.v.emplace_back(V);
  }
  return worst;
}

// The per-channel fit into fit.factors and its report (options.on_rank called with each rank's); returns the
// worst channel's node error.
double store_separate(const SampledNodes& nodes, const HalfAngleFitOptions& o, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                      std::chrono::steady_clock::time_point t0, HalfAngleFit& fit) {
  std::vector<ChannelFit> cf;
  std::vector<double> norm2, e2;
  std::function<bool(int)> after_rank;
  if (o.on_rank)
    after_rank = [&](int rank) {
      HalfAngleFit at = fit;  // the grids, factors not yet set
      separate_result(cf, norm2, e2, rank, a, b, at);
      finish_fit(o, t0, at);
      return o.on_rank(at);
    };
  const int rank = grow_ranks(nodes, o, a, b, cf, norm2, e2, fit.report.sweeps_by_rank, after_rank);
  return separate_result(cf, norm2, e2, rank, a, b, fit);
}

}  // namespace

HalfAngleFit fit_half_angle(const PairSampler& sampler, int channels, const HalfAngleFitOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const SerialEigen serial;
  check_fit_options(channels, o);
  HalfAngleFit fit;
  HalfAngleFactors& F = fit.factors;
  F.quantity = o.quantity;
  F.corners = o.corners;
  F.centred = o.centred;
  F.isotropic = o.isotropic;
  F.h_warp = o.h_warp;
  if (!o.isotropic) F.h_axis = o.h_axis, F.h_scale_1 = o.h_scale_1, F.h_scale_2 = o.h_scale_2;
  F.n_t = o.n_t;
  F.n_phi_h = o.isotropic ? 1 : o.n_phi_h;
  F.n_theta_d = o.n_theta_d;
  F.n_phi_d = o.n_phi_d;
  const Eigen::VectorXd a = half_angle_h_weights(F), b = half_angle_d_weights(F);
  const SampledNodes nodes = sample_nodes(sampler, channels, o, F, a, b, &fit.report.valid_fraction);
  fit.report.missing_nodes = nodes.missing;
  const double worst = o.shared_channels ? store_shared(nodes, o, a, b, t0, fit) : store_separate(nodes, o, a, b, t0, fit);
  finish_fit(o, t0, fit);
  if (o.fixed_rank == 0 && worst > o.target) {
    std::ostringstream s;
    s << "half-angle fit: rank " << o.max_rank << " reaches a weighted relative error of " << worst
      << ", above the target " << o.target << " (grid n_t = " << F.n_t << ", n_phi_h = " << F.n_phi_h
      << ", n_theta_d = " << F.n_theta_d << ", n_phi_d = " << F.n_phi_d << "); raise max_rank or the target";
    throw UnsupportedError(s.str());
  }
  return fit;
}

}  // namespace icobrdf
