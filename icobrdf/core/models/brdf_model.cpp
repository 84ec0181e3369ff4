#include "icobrdf/core/models/brdf_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

double BrdfModel::eval(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  RowMatrix3d a(1, 3), b(1, 3);
  a.row(0) = wi.transpose();
  b.row(0) = wr.transpose();
  Eigen::MatrixXd out(1, channels());
  eval(a, b, out);
  return out(0, 0);
}

void check_pair_shapes(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::Ref<Eigen::MatrixXd>& out,
                       int channels) {
  if (wi.rows() != wr.rows() || out.rows() != wi.rows() || out.cols() != channels)
    throw ArgumentError("BRDF evaluation: shapes wi " + std::to_string(wi.rows()) + "x3, wr " +
                        std::to_string(wr.rows()) + "x3, out " + std::to_string(out.rows()) + "x" +
                        std::to_string(out.cols()) + "; expected equal rows and out with " +
                        std::to_string(channels) + " column(s)");
}

void ScalarBrdfModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi, wr, out, 1);
  for (Eigen::Index r = 0; r < wi.rows(); ++r) {
    Eigen::Vector3d a = wi.row(r).transpose(), b = wr.row(r).transpose();
    if (a.z() < -kHorizonSlack || b.z() < -kHorizonSlack) {
      out(r, 0) = 0.0;
      continue;
    }
    a.z() = std::max(a.z(), 0.0);
    b.z() = std::max(b.z(), 0.0);
    out(r, 0) = value(a, b);
  }
}

void MirrorModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi, wr, out, 1);
  out.setZero();
}

void RetroreflectorModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi, wr, out, 1);
  out.setZero();
}

SumModel::SumModel(std::vector<Term> terms) {
  for (auto& t : terms) {
    if (!t.model) throw ArgumentError("model sum: a term has no model");
    if (!std::isfinite(t.weight) || t.weight < 0.0)
      throw ArgumentError("model sum: weight of '" + quoted_text(t.model->spec()) + "' must be finite and >= 0, got " +
                          format_parameter(t.weight));
    if (const auto* s = dynamic_cast<const SumModel*>(t.model.get())) {
      for (const auto& inner : s->terms()) terms_.push_back({t.weight * inner.weight, inner.model});
    } else {
      terms_.push_back(std::move(t));
    }
  }
  if (terms_.empty()) throw ArgumentError("model sum: no terms");
  for (const auto& t : terms_) {
    const int c = t.model->channels();
    if (c == 1) continue;
    if (channels_ != 1 && channels_ != c)
      throw ArgumentError("model sum '" + quoted_text(spec()) + "': terms have " + std::to_string(channels_) + " and " +
                          std::to_string(c) + " channels; expected equal counts or 1");
    channels_ = c;
  }
}

void BrdfModel::eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  const RowMatrix3d wi_all = wi.transpose().replicate(wr.rows(), 1);
  eval(wi_all, wr, out);
}

namespace {

// out = sum of weight x each term's values, a 1-channel term broadcast; eval_term(model, part) fills part.
template <class EvalTerm>
void sum_terms(const std::vector<SumModel::Term>& terms, int channels, Eigen::Index rows, Eigen::Ref<Eigen::MatrixXd> out,
               EvalTerm eval_term) {
  out.setZero();
  Eigen::MatrixXd part;
  for (const auto& t : terms) {
    const int c = t.model->channels();
    part.resize(rows, c);
    eval_term(*t.model, part);
    if (c == channels) {
      out += t.weight * part;
    } else {  // 1-channel term broadcast
      for (int k = 0; k < channels; ++k) out.col(k) += t.weight * part.col(0);
    }
  }
}

}  // namespace

void SumModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi, wr, out, channels_);
  sum_terms(terms_, channels_, wi.rows(), out, [&](const BrdfModel& m, Eigen::MatrixXd& part) { m.eval(wi, wr, part); });
}

void SumModel::eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wr, wr, out, channels_);
  sum_terms(terms_, channels_, wr.rows(), out, [&](const BrdfModel& m, Eigen::MatrixXd& part) { m.eval_row(wi, wr, part); });
}

std::vector<DeltaPart> SumModel::delta_parts() const {
  std::map<int, double> by_kind;
  for (const auto& t : terms_)
    for (const auto& d : t.model->delta_parts()) by_kind[d.kind] += t.weight * d.weight;
  std::vector<DeltaPart> parts;
  for (const auto& [kind, w] : by_kind) parts.push_back({static_cast<DeltaPart::Kind>(kind), w});
  return parts;
}

bool SumModel::is_isotropic() const {
  return std::all_of(terms_.begin(), terms_.end(), [](const Term& t) { return t.model->is_isotropic(); });
}

bool SumModel::is_reciprocal() const {
  return std::all_of(terms_.begin(), terms_.end(), [](const Term& t) { return t.model->is_reciprocal(); });
}

std::string SumModel::spec() const {
  std::string s;
  for (const auto& t : terms_) {
    if (!s.empty()) s += "+";
    if (t.weight != 1.0) s += format_parameter(t.weight) + "*";
    s += t.model->spec();
  }
  return s;
}

std::string format_parameter(double x) {
  char buf[64];
  const double ax = std::abs(x);
  if (ax == 0.0 || (ax >= 1e-5 && ax < 1e15)) {  // plain decimal notation when it is exact and short
    for (int decimals = 0; decimals <= 20; ++decimals) {
      std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
      if (std::strtod(buf, nullptr) == x) return buf;
    }
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, x);
    if (std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

std::string format_model_spec(const std::string& name, const std::vector<std::pair<std::string, std::string>>& params) {
  std::string s = name;
  for (std::size_t k = 0; k < params.size(); ++k)
    s += (k == 0 ? ":" : ",") + params[k].first + "=" + params[k].second;
  return s;
}

}  // namespace icobrdf
