#include "icobrdf/io/merl.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"
#include "icobrdf/io/atomic_write.hpp"

namespace icobrdf {

namespace {

constexpr double kHalfPi = M_PI / 2;

// Rotation of v about the z axis (or the y axis) by `angle` (right-handed).
Eigen::Vector3d rotate_z(const Eigen::Vector3d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}
Eigen::Vector3d rotate_y(const Eigen::Vector3d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() + s * v.z(), v.y(), -s * v.x() + c * v.z()};
}

double clamped_acos(double z) { return std::acos(std::clamp(z, -1.0, 1.0)); }

std::uint32_t bswap32(std::uint32_t x) {
  return (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);
}

std::int32_t le_int32(const unsigned char* p) {
  const std::uint32_t u = static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
                          (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
  std::int32_t s;
  std::memcpy(&s, &u, 4);
  return s;
}

double le_double(const unsigned char* p) {
  std::uint64_t u = 0;
  for (int k = 7; k >= 0; --k) u = (u << 8) | p[k];
  double d;
  std::memcpy(&d, &u, 8);
  return d;
}

void put_le_double(double d, unsigned char* p) {
  std::uint64_t u;
  std::memcpy(&u, &d, 8);
  for (int k = 0; k < 8; ++k) p[k] = static_cast<unsigned char>(u >> (8 * k));
}

void put_le_int32(std::int32_t s, unsigned char* p) {
  std::uint32_t u;
  std::memcpy(&u, &s, 4);
  for (int k = 0; k < 4; ++k) p[k] = static_cast<unsigned char>(u >> (8 * k));
}

std::string dims_text(std::int64_t a, std::int64_t b, std::int64_t c) {
  return std::to_string(a) + " x " + std::to_string(b) + " x " + std::to_string(c);
}

const std::string kStandardDims = "90 x 90 x 180 (theta_h x theta_d x phi_d)";

// Header checks, in order of specificity; throws InputError with a one-line message.
void check_dims(const std::string& path, std::int32_t d0, std::int32_t d1, std::int32_t d2) {
  const std::int32_t d[3] = {d0, d1, d2};
  std::int32_t sw[3];
  for (int k = 0; k < 3; ++k) {
    std::uint32_t u;
    std::memcpy(&u, &d[k], 4);
    u = bswap32(u);
    std::memcpy(&sw[k], &u, 4);
  }
  if (d0 == 90 && d1 == 90 && d2 == 180) return;
  if (sw[0] == 90 && sw[1] == 90 && sw[2] == 180)
    throw InputError(path + ": byte-swapped MERL header: dims read " + dims_text(d0, d1, d2) +
                     " as little-endian int32 are " + dims_text(sw[0], sw[1], sw[2]) +
                     " byte-swapped (a big-endian file); expected little-endian " + kStandardDims);
  if (d0 <= 0 || d1 <= 0 || d2 <= 0)
    throw InputError(path + ": MERL dims must be positive, expected " + kStandardDims + ", found " + dims_text(d0, d1, d2));
  // Each dim < 2^31, so d0 d1 < 2^62 and, when d0 d1 <= INT32_MAX, (d0 d1) d2 < 2^62: no int64 overflow.
  const std::int64_t limit = std::numeric_limits<std::int32_t>::max();
  const bool overflow = static_cast<std::int64_t>(d0) * d1 > limit || (static_cast<std::int64_t>(d0) * d1) * d2 > limit;
  if (overflow)
    throw InputError(path + ": MERL dims " + dims_text(d0, d1, d2) + ": sample count overflows int32 (max " +
                     std::to_string(limit) + "); expected " + kStandardDims);
  const std::int64_t product = static_cast<std::int64_t>(d0) * d1 * d2;
  std::int32_t s[3] = {d0, d1, d2};
  std::sort(s, s + 3);
  if (s[0] == 90 && s[1] == 90 && s[2] == 180)
    throw InputError(path + ": MERL dims " + dims_text(d0, d1, d2) + " are a permutation of the standard " + kStandardDims +
                     "; the axis order is not guessed");
  throw InputError(path + ": MERL dims expected " + kStandardDims + ", found " + dims_text(d0, d1, d2) + " (" +
                   std::to_string(product) + " samples per channel)");
}

}  // namespace

HalfDiffAngles half_diff_from_directions(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  Eigen::Vector3d h = wi + wr;
  const double n = h.norm();
  h = n > 0 ? Eigen::Vector3d(h / n) : Eigen::Vector3d(0, 0, 1);
  HalfDiffAngles a{};
  a.theta_h = clamped_acos(h.z());
  a.phi_h = std::atan2(h.y(), h.x());
  const Eigen::Vector3d d = rotate_y(rotate_z(wi, -a.phi_h), -a.theta_h);
  a.theta_d = clamped_acos(d.z());
  a.phi_d = std::atan2(d.y(), d.x());
  return a;
}

void directions_from_half_diff(const HalfDiffAngles& a, Eigen::Vector3d& wi, Eigen::Vector3d& wr) {
  const Eigen::Vector3d d(std::sin(a.theta_d) * std::cos(a.phi_d), std::sin(a.theta_d) * std::sin(a.phi_d),
                          std::cos(a.theta_d));
  const Eigen::Vector3d h(std::sin(a.theta_h) * std::cos(a.phi_h), std::sin(a.theta_h) * std::sin(a.phi_h),
                          std::cos(a.theta_h));
  wi = rotate_z(rotate_y(d, a.theta_h), a.phi_h);
  wr = 2.0 * wi.dot(h) * h - wi;
}

MerlBin merl_bin(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  const HalfDiffAngles a = half_diff_from_directions(wi, wr);
  MerlBin b{};
  const double th = a.theta_h <= 0 ? 0.0 : std::sqrt(a.theta_h / kHalfPi) * kMerlThetaHalfRes;
  b.theta_h = std::clamp(static_cast<int>(th), 0, kMerlThetaHalfRes - 1);
  b.theta_d = std::clamp(static_cast<int>(a.theta_d / kHalfPi * kMerlThetaDiffRes), 0, kMerlThetaDiffRes - 1);
  double pd = a.phi_d;
  if (pd < 0) pd += M_PI;  // reciprocity fold to [0, pi]
  b.phi_d = std::clamp(static_cast<int>(pd / M_PI * kMerlPhiDiffRes), 0, kMerlPhiDiffRes - 1);
  return b;
}

HalfDiffAngles merl_node(const MerlBin& b) {
  const double u = (b.theta_h + 0.5) / kMerlThetaHalfRes;
  return {kHalfPi * u * u, 0.0, kHalfPi * (b.theta_d + 0.5) / kMerlThetaDiffRes, M_PI * (b.phi_d + 0.5) / kMerlPhiDiffRes};
}

MerlTable read_merl(const std::string& path) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path + ": no such MERL file");
  if (!S_ISREG(st.st_mode)) throw InputError(path + ": not a regular file (expected a MERL .binary file)");
  const std::int64_t size = st.st_size;
  if (size == 0)
    throw InputError(path + ": empty file, expected a MERL file of " + std::to_string(kMerlFileBytes) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  if (size < 12)
    throw InputError(path + ": truncated MERL header: " + std::to_string(size) + " bytes, expected 12 (three int32 dims)");
  unsigned char header[12];
  in.read(reinterpret_cast<char*>(header), 12);
  if (!in) throw InputError(path + ": cannot read the 12-byte MERL header");
  check_dims(path, le_int32(header), le_int32(header + 4), le_int32(header + 8));
  if (size < kMerlFileBytes) {
    const std::int64_t data = size - 12;
    throw InputError(path + ": truncated MERL file: " + std::to_string(size) + " bytes, expected " +
                     std::to_string(kMerlFileBytes) + " (" + std::to_string(kMerlFileBytes - size) +
                     " bytes missing; the data stop after " + std::to_string(data / 8) + " of " +
                     std::to_string(3 * kMerlSamplesPerChannel) + " doubles)");
  }
  if (size > kMerlFileBytes)
    throw InputError(path + ": " + std::to_string(size - kMerlFileBytes) +
                     " trailing bytes after the 3 x 90 x 90 x 180 doubles (file " + std::to_string(size) +
                     " bytes, expected " + std::to_string(kMerlFileBytes) + ")");
  MerlTable t;
  t.path = path;
  t.f.resize(static_cast<size_t>(3 * kMerlSamplesPerChannel));
  std::vector<unsigned char> buf(static_cast<size_t>(8 * 65536));
  std::int64_t done = 0;
  while (done < 3 * kMerlSamplesPerChannel) {
    const std::int64_t n = std::min<std::int64_t>(65536, 3 * kMerlSamplesPerChannel - done);
    in.read(reinterpret_cast<char*>(buf.data()), n * 8);
    if (in.gcount() != n * 8)
      throw InputError(path + ": read failed after " + std::to_string(12 + done * 8) + " bytes (file changed while reading?)");
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t idx = done + k;
      const int c = static_cast<int>(idx / kMerlSamplesPerChannel);
      const double v = le_double(buf.data() + 8 * k);
      if (!std::isfinite(v)) {
        const std::int64_t r = idx % kMerlSamplesPerChannel;
        throw InputError(path + ": sample " + std::to_string(r) + " of channel " + "RGB"[c] + " (theta_h bin " +
                         std::to_string(r / (kMerlThetaDiffRes * kMerlPhiDiffRes)) + ", theta_d bin " +
                         std::to_string((r / kMerlPhiDiffRes) % kMerlThetaDiffRes) + ", phi_d bin " +
                         std::to_string(r % kMerlPhiDiffRes) + ") expected a finite number or -1, found " +
                         (std::isnan(v) ? "NaN" : "Inf"));
      }
      if (v < 0) {
        t.f[static_cast<size_t>(idx)] = std::numeric_limits<double>::quiet_NaN();
        ++t.missing[static_cast<size_t>(c)];
      } else {
        t.f[static_cast<size_t>(idx)] = v * kMerlChannelScale[static_cast<size_t>(c)];
      }
    }
    done += n;
  }
  if (t.missing_total() == 3 * kMerlSamplesPerChannel)
    throw InputError(path + ": all " + std::to_string(3 * kMerlSamplesPerChannel) +
                     " MERL samples are missing (negative), expected at least one measured sample");
  return t;
}

void write_merl(const std::string& path, const BrdfModel& model, const std::function<bool(const MerlBin&)>& missing) {
  const int ch = model.channels();
  if (ch != 1 && ch != 3)
    throw ArgumentError("MERL table: model '" + quoted_text(model.spec()) + "' has " + std::to_string(ch) + " channels, expected 1 or 3");
  std::vector<unsigned char> bytes(static_cast<size_t>(kMerlFileBytes));
  put_le_int32(kMerlThetaHalfRes, bytes.data());
  put_le_int32(kMerlThetaDiffRes, bytes.data() + 4);
  put_le_int32(kMerlPhiDiffRes, bytes.data() + 8);
  // One theta_h row of nodes (90 x 180 pairs) per model call.
  const int row = kMerlThetaDiffRes * kMerlPhiDiffRes;
  RowMatrix3d wi(row, 3), wr(row, 3);
  Eigen::MatrixXd out(row, ch);
  for (int ih = 0; ih < kMerlThetaHalfRes; ++ih) {
    for (int id = 0; id < kMerlThetaDiffRes; ++id)
      for (int ip = 0; ip < kMerlPhiDiffRes; ++ip) {
        Eigen::Vector3d a, b;
        directions_from_half_diff(merl_node({ih, id, ip}), a, b);
        const int r = ip + kMerlPhiDiffRes * id;
        wi.row(r) = a.transpose();
        wr.row(r) = b.transpose();
      }
    model.eval(wi, wr, out);
    for (int r = 0; r < row; ++r) {
      const MerlBin bin{ih, r / kMerlPhiDiffRes, r % kMerlPhiDiffRes};
      const bool gone = missing && missing(bin);
      const bool above = wi(r, 2) >= 0 && wr(r, 2) >= 0;
      for (int c = 0; c < 3; ++c) {
        const double f = out(r, ch == 3 ? c : 0);
        if (!gone && above && (!std::isfinite(f) || f < 0))
          throw ArgumentError("MERL table: model '" + quoted_text(model.spec()) + "' gives " + std::to_string(f) +
                              " at a table node; expected a finite value >= 0");
        const double v = gone ? -1.0 : (std::isfinite(f) ? std::max(f, 0.0) : 0.0) / kMerlChannelScale[static_cast<size_t>(c)];
        put_le_double(v, bytes.data() + 12 + 8 * (c * kMerlSamplesPerChannel + bin.flat()));
      }
    }
  }
  atomic_write_bytes(path, bytes.data(), bytes.size());
}

void MerlModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  check_pair_shapes(wi, wr, out, 3);
  for (Eigen::Index r = 0; r < wi.rows(); ++r) {
    if (wi(r, 2) < -kHorizonSlack || wr(r, 2) < -kHorizonSlack) {
      out.row(r).setZero();
      continue;
    }
    Eigen::Vector3d a = wi.row(r).transpose(), b = wr.row(r).transpose();
    a.z() = std::max(a.z(), 0.0);
    b.z() = std::max(b.z(), 0.0);
    const MerlBin bin = merl_bin(a, b);
    for (int c = 0; c < 3; ++c) out(r, c) = table_->at(c, bin);
  }
}

MerlSamples merl_samples(const MerlTable& t) {
  MerlSamples s;
  std::vector<std::int64_t> keep;
  std::vector<Eigen::Vector3d> a, b;
  const double dpd = M_PI / kMerlPhiDiffRes;
  std::vector<double> w;
  for (int ih = 0; ih < kMerlThetaHalfRes; ++ih) {
    const double u0 = static_cast<double>(ih) / kMerlThetaHalfRes, u1 = (ih + 1.0) / kMerlThetaHalfRes;
    const double h_int = std::cos(kHalfPi * u0 * u0) - std::cos(kHalfPi * u1 * u1);  // integral of sin(theta_h)
    for (int id = 0; id < kMerlThetaDiffRes; ++id) {
      const double d0 = kHalfPi * id / kMerlThetaDiffRes, d1 = kHalfPi * (id + 1) / kMerlThetaDiffRes;
      const double d_int = 0.5 * (std::sin(d1) * std::sin(d1) - std::sin(d0) * std::sin(d0));  // of cos sin
      const double weight = 4.0 * h_int * d_int * dpd * 2.0 * M_PI * 2.0;
      for (int ip = 0; ip < kMerlPhiDiffRes; ++ip) {
        const MerlBin bin{ih, id, ip};
        Eigen::Vector3d x, y;
        directions_from_half_diff(merl_node(bin), x, y);
        if (!(x.z() > 0 && y.z() > 0)) {
          ++s.below_horizon;
          continue;
        }
        if (std::isnan(t.at(0, bin)) || std::isnan(t.at(1, bin)) || std::isnan(t.at(2, bin))) {
          ++s.missing;
          continue;
        }
        keep.push_back(bin.flat());
        a.push_back(x);
        b.push_back(y);
        w.push_back(weight);
      }
    }
  }
  const auto n = static_cast<Eigen::Index>(keep.size());
  s.wi.resize(n, 3);
  s.wr.resize(n, 3);
  s.values.resize(n, 3);
  s.weights.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    s.wi.row(k) = a[static_cast<size_t>(k)].transpose();
    s.wr.row(k) = b[static_cast<size_t>(k)].transpose();
    s.weights[k] = w[static_cast<size_t>(k)];
    for (int c = 0; c < 3; ++c) s.values(k, c) = t.f[static_cast<size_t>(c * kMerlSamplesPerChannel + keep[static_cast<size_t>(k)])];
  }
  s.bins = std::move(keep);
  return s;
}

}  // namespace icobrdf
