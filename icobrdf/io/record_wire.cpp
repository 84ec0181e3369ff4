#include "icobrdf/io/record_wire.hpp"

#include <cstring>
#include <type_traits>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

constexpr char kWireTag[] = "icobrdf-record-wire";
constexpr std::size_t kWireTagBytes = sizeof(kWireTag) - 1;

class WireWriter {
 public:
  std::string bytes;
  template <class T>
  void raw(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void integer(std::int64_t v) { raw(v); }
  void flag(bool v) { raw(static_cast<std::uint8_t>(v ? 1 : 0)); }
  void real(double v) { raw(v); }
  void text(const std::string& s) {
    integer(static_cast<std::int64_t>(s.size()));
    bytes.append(s);
  }
  template <class Scalar>
  void values(const Scalar* p, std::int64_t n) {
    if (n == 0) return;  // an empty matrix's data() may be null
    bytes.append(reinterpret_cast<const char*>(p), static_cast<std::size_t>(n) * sizeof(Scalar));
  }
  // rows, cols, then the entries in the matrix's own storage order.
  template <class M>
  void matrix(const M& m) {
    integer(m.rows());
    integer(m.cols());
    values(m.data(), static_cast<std::int64_t>(m.size()));
  }
  void reals(const std::vector<double>& v) {
    integer(static_cast<std::int64_t>(v.size()));
    values(v.data(), static_cast<std::int64_t>(v.size()));
  }
};

class WireReader {
 public:
  WireReader(const std::string& bytes, const std::string& name) : b_(bytes), name_(name) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(name_ + ": byte " + std::to_string(at_) + ": " + what);
  }
  void need(std::uint64_t n, const char* what) const {
    if (n > b_.size() - at_)
      fail(std::string(what) + ": expected " + std::to_string(n) + " more bytes, found " + std::to_string(b_.size() - at_));
  }
  template <class T>
  T raw(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::int64_t integer(const char* what) { return raw<std::int64_t>(what); }
  int small(const char* what) {
    const std::int64_t v = integer(what);
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      fail(std::string(what) + ": expected a 32-bit integer, found " + std::to_string(v));
    return static_cast<int>(v);
  }
  bool flag(const char* what) {
    const auto v = raw<std::uint8_t>(what);
    if (v > 1) fail(std::string(what) + ": expected a flag of 0 or 1, found " + std::to_string(v));
    return v == 1;
  }
  double real(const char* what) { return raw<double>(what); }
  // A count of items of at least `item_bytes` each that must fit in the bytes left.
  std::int64_t count(const char* what, std::uint64_t item_bytes) {
    const std::int64_t n = integer(what);
    if (n < 0) fail(std::string(what) + ": expected a count >= 0, found " + std::to_string(n));
    if (item_bytes > 0 && static_cast<std::uint64_t>(n) > (b_.size() - at_) / item_bytes)
      fail(std::string(what) + ": " + std::to_string(n) + " items do not fit in the " + std::to_string(b_.size() - at_) + " bytes left");
    return n;
  }
  std::string text(const char* what) {
    const auto n = static_cast<std::size_t>(count(what, 1));
    std::string s = b_.substr(at_, n);
    at_ += n;
    return s;
  }
  template <class Scalar>
  void values(Scalar* p, std::int64_t n, const char* what) {
    if (n == 0) return;  // an empty matrix's data() may be null
    need(static_cast<std::uint64_t>(n) * sizeof(Scalar), what);
    std::memcpy(p, b_.data() + at_, static_cast<std::size_t>(n) * sizeof(Scalar));
    at_ += static_cast<std::size_t>(n) * sizeof(Scalar);
  }
  template <class M>
  M matrix(const char* what) {
    const std::int64_t rows = count(what, 0), cols = count(what, 0);
    using Scalar = typename M::Scalar;
    if (rows > 0 && static_cast<std::uint64_t>(cols) > (b_.size() - at_) / sizeof(Scalar) / static_cast<std::uint64_t>(rows))
      fail(std::string(what) + ": " + std::to_string(rows) + " x " + std::to_string(cols) + " entries do not fit in the " +
           std::to_string(b_.size() - at_) + " bytes left");
    if (M::ColsAtCompileTime != Eigen::Dynamic && cols != M::ColsAtCompileTime)
      fail(std::string(what) + ": expected " + std::to_string(M::ColsAtCompileTime) + " columns, found " + std::to_string(cols));
    M m(rows, cols);
    values(m.data(), rows * cols, what);
    return m;
  }
  std::vector<double> reals(const char* what) {
    std::vector<double> v(static_cast<std::size_t>(count(what, sizeof(double))));
    values(v.data(), static_cast<std::int64_t>(v.size()), what);
    return v;
  }
  void finish() const {
    if (at_ != b_.size()) fail("expected the end of the record, found " + std::to_string(b_.size() - at_) + " more bytes");
  }
  std::size_t at_ = 0;

 private:
  const std::string& b_;
  const std::string& name_;
};

void put_sample_fit(WireWriter& w, const SampleFitRecord& f) {
  w.integer(f.samples);
  w.integer(f.unknowns);
  w.integer(f.effective_rank);
  w.real(f.condition);
  w.reals(f.residual_rms);
  w.reals(f.noise_sigma);
  w.real(f.cv_rms);
  w.integer(f.cv_folds);
  w.real(f.tikhonov);
  w.real(f.tikhonov_power);
  w.text(f.order_choice);
  w.text(f.tikhonov_choice);
  w.text(f.fallback);
  w.text(f.solver);
  w.real(f.effective_dof);
  w.text(f.class_choice);
  w.real(f.cv_rms_isotropic);
  w.real(f.cv_rms_general);
  w.matrix(f.standard_error);
}

SampleFitRecord get_sample_fit(WireReader& r) {
  SampleFitRecord f;
  f.samples = r.integer("sample_fit.samples");
  f.unknowns = r.small("sample_fit.unknowns");
  f.effective_rank = r.small("sample_fit.effective_rank");
  f.condition = r.real("sample_fit.condition");
  f.residual_rms = r.reals("sample_fit.residual_rms");
  f.noise_sigma = r.reals("sample_fit.noise_sigma");
  f.cv_rms = r.real("sample_fit.cv_rms");
  f.cv_folds = r.small("sample_fit.cv_folds");
  f.tikhonov = r.real("sample_fit.tikhonov");
  f.tikhonov_power = r.real("sample_fit.tikhonov_power");
  f.order_choice = r.text("sample_fit.order_choice");
  f.tikhonov_choice = r.text("sample_fit.tikhonov_choice");
  f.fallback = r.text("sample_fit.fallback");
  f.solver = r.text("sample_fit.solver");
  f.effective_dof = r.real("sample_fit.effective_dof");
  f.class_choice = r.text("sample_fit.class_choice");
  f.cv_rms_isotropic = r.real("sample_fit.cv_rms_isotropic");
  f.cv_rms_general = r.real("sample_fit.cv_rms_general");
  f.standard_error = r.matrix<Eigen::MatrixXd>("sample_fit.standard_error");
  return f;
}

void put_lobe(WireWriter& w, const HalfAngleFactors& f) {
  w.integer(static_cast<std::int64_t>(f.quantity));
  w.flag(f.isotropic);
  w.real(f.h_warp);
  w.integer(static_cast<std::int64_t>(f.corners));
  w.flag(f.centred);
  w.real(f.h_axis);
  w.real(f.h_scale_1);
  w.real(f.h_scale_2);
  for (int n : {f.n_t, f.n_phi_h, f.n_theta_d, f.n_phi_d, f.rank}) w.integer(n);
  w.integer(static_cast<std::int64_t>(f.u.size()));
  for (const auto& m : f.u) w.matrix(m);
  w.integer(static_cast<std::int64_t>(f.v.size()));
  for (const auto& m : f.v) w.matrix(m);
  w.integer(static_cast<std::int64_t>(f.precision));
  w.matrix(f.channel_scales);
}

HalfAngleFactors get_lobe(WireReader& r) {
  HalfAngleFactors f;
  const std::int64_t q = r.integer("lobe.quantity");
  if (q < 0 || q > static_cast<std::int64_t>(HalfAngleQuantity::MeanCosine)) r.fail("lobe.quantity: unknown value " + std::to_string(q));
  f.quantity = static_cast<HalfAngleQuantity>(q);
  f.isotropic = r.flag("lobe.isotropic");
  f.h_warp = r.real("lobe.h_warp");
  const std::int64_t c = r.integer("lobe.corners");
  if (c < 0 || c > static_cast<std::int64_t>(HorizonCorners::Valid)) r.fail("lobe.corners: unknown value " + std::to_string(c));
  f.corners = static_cast<HorizonCorners>(c);
  f.centred = r.flag("lobe.centred");
  f.h_axis = r.real("lobe.h_axis");
  f.h_scale_1 = r.real("lobe.h_scale_1");
  f.h_scale_2 = r.real("lobe.h_scale_2");
  f.n_t = r.small("lobe.n_t");
  f.n_phi_h = r.small("lobe.n_phi_h");
  f.n_theta_d = r.small("lobe.n_theta_d");
  f.n_phi_d = r.small("lobe.n_phi_d");
  f.rank = r.small("lobe.rank");
  f.u.resize(static_cast<std::size_t>(r.count("lobe.u", 16)));
  for (auto& m : f.u) m = r.matrix<RowMatrixXd>("lobe.u");
  f.v.resize(static_cast<std::size_t>(r.count("lobe.v", 16)));
  for (auto& m : f.v) m = r.matrix<RowMatrixXd>("lobe.v");
  const std::int64_t p = r.integer("lobe.precision");
  if (p < 0 || p > static_cast<std::int64_t>(FactorPrecision::Int8)) r.fail("lobe.precision: unknown value " + std::to_string(p));
  f.precision = static_cast<FactorPrecision>(p);
  f.channel_scales = r.matrix<RowMatrixXd>("lobe.channel_scales");
  return f;
}

}  // namespace

std::string record_wire(const MaterialRecord& rec) {
  WireWriter w;
  w.bytes.append(kWireTag, kWireTagBytes);
  w.raw(kRecordWireVersion);
  w.text(rec.name);
  const Spectrum& s = rec.spectrum;
  w.integer(s.order);
  w.flag(s.isotropic);
  w.flag(s.cosine);
  w.integer(static_cast<std::int64_t>(s.channels.size()));
  for (const auto& c : s.channels) w.matrix(c);
  w.text(s.source);
  w.integer(static_cast<std::int64_t>(s.channel_names.size()));
  for (const auto& n : s.channel_names) w.text(n);
  w.text(s.filter);
  w.integer(s.level);
  w.text(s.grid_kind);
  w.real(s.gram_error);
  w.real(s.reciprocity_violation);
  w.real(s.anisotropy_fraction);
  w.real(s.max_albedo);
  w.flag(s.sample_fit.has_value());
  if (s.sample_fit) put_sample_fit(w, *s.sample_fit);
  w.matrix(rec.ibsss);
  w.matrix(rec.ibsss_indices);
  w.flag(rec.lobe.has_value());
  if (rec.lobe) put_lobe(w, *rec.lobe);
  w.integer(static_cast<std::int64_t>(rec.lut.size()));
  for (const auto& l : rec.lut) w.matrix(l);
  w.flag(rec.lut_float32);
  w.real(rec.lut_max_rounding_error);
  w.integer(static_cast<std::int64_t>(rec.figures.size()));
  for (const auto& [k, v] : rec.figures) {
    w.text(k);
    w.real(v);
  }
  w.integer(static_cast<std::int64_t>(rec.labels.size()));
  for (const auto& [k, v] : rec.labels) {
    w.text(k);
    w.text(v);
  }
  return std::move(w.bytes);
}

MaterialRecord read_record_wire(const std::string& bytes, const std::string& name) {
  WireReader r(bytes, name);
  if (bytes.size() < kWireTagBytes || bytes.compare(0, kWireTagBytes, kWireTag) != 0)
    r.fail(std::string("expected a record starting with '") + kWireTag + "', found other bytes (" + std::to_string(bytes.size()) + " in all)");
  r.at_ = kWireTagBytes;
  const auto version = r.raw<std::uint32_t>("version");
  if (version != kRecordWireVersion)
    r.fail("expected record version " + std::to_string(kRecordWireVersion) + ", found " + std::to_string(version));
  MaterialRecord rec;
  rec.name = r.text("name");
  Spectrum& s = rec.spectrum;
  s.order = r.small("order");
  s.isotropic = r.flag("isotropic");
  s.cosine = r.flag("cosine");
  s.channels.resize(static_cast<std::size_t>(r.count("channels", 16)));
  for (auto& c : s.channels) c = r.matrix<Eigen::MatrixXd>("channel");
  s.source = r.text("source");
  s.channel_names.resize(static_cast<std::size_t>(r.count("channel_names", 8)));
  for (auto& n : s.channel_names) n = r.text("channel_name");
  s.filter = r.text("filter");
  s.level = r.small("level");
  s.grid_kind = r.text("grid_kind");
  s.gram_error = r.real("gram_error");
  s.reciprocity_violation = r.real("reciprocity_violation");
  s.anisotropy_fraction = r.real("anisotropy_fraction");
  s.max_albedo = r.real("max_albedo");
  if (r.flag("sample_fit")) s.sample_fit = get_sample_fit(r);
  rec.ibsss = r.matrix<Eigen::MatrixXd>("ibsss");
  rec.ibsss_indices = r.matrix<RowMatrix3i>("ibsss_indices");
  if (r.flag("lobe")) rec.lobe = get_lobe(r);
  rec.lut.resize(static_cast<std::size_t>(r.count("lut", 16)));
  for (auto& l : rec.lut) l = r.matrix<Eigen::MatrixXd>("lut");
  rec.lut_float32 = r.flag("lut_float32");
  rec.lut_max_rounding_error = r.real("lut_max_rounding_error");
  const std::int64_t figures = r.count("figures", 16);
  for (std::int64_t i = 0; i < figures; ++i) {
    std::string k = r.text("figure name");
    rec.figures[k] = r.real("figure");
  }
  const std::int64_t labels = r.count("labels", 16);
  for (std::int64_t i = 0; i < labels; ++i) {
    std::string k = r.text("label name");
    rec.labels[k] = r.text("label");
  }
  r.finish();
  return rec;
}

}  // namespace icobrdf
