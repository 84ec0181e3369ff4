#pragma once
// Shared helpers of the io tests: scratch folders, a small synthetic Grid and Spectrum, and running a
// reader in a child process with a timeout (HDF5 may hang or abort on crafted files).
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf::test {

// A fresh folder under /tmp, removed (with its content) when the object dies.
class ScratchDir {
 public:
  ScratchDir() {
    char tmpl[] = "/tmp/icobrdf-io-test-XXXXXX";
    const char* d = ::mkdtemp(tmpl);
    if (!d) std::abort();
    path_ = d;
  }
  ~ScratchDir() {
    const std::string cmd = "chmod -R u+rwx '" + path_ + "' 2>/dev/null; rm -rf '" + path_ + "'";
    if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "could not remove %s\n", path_.c_str());
  }
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }
  // Names in the folder (excluding . and ..).
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    FILE* p = ::popen(("ls -A '" + path_ + "'").c_str(), "r");
    char line[4096];
    while (p && std::fgets(line, sizeof line, p)) {
      std::string s(line);
      if (!s.empty() && s.back() == '\n') s.pop_back();
      out.push_back(s);
    }
    if (p) ::pclose(p);
    return out;
  }

 private:
  std::string path_;
};

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Eight cells: two polar bands (theta in [0, pi/3] and [pi/3, pi/2]) times four azimuth quadrants.
// Solid angle of a band-quadrant cell: (cos(theta0) - cos(theta1)) * pi / 2 (integral of sin(theta)
// dtheta dphi), so the upper cells have pi/4 sr and the lower ones pi/4 sr too (cos 60 deg = 1/2).
// Upper cells carry one cubature point, lower cells two with half the weight each.
inline Grid synthetic_grid() {
  Grid g;
  g.kind = GridKind::Custom;
  g.level = 1;
  g.cubature_degree = 1;
  const double bands[3] = {0.0, M_PI / 3, M_PI / 2};
  auto dir = [](double th, double ph) { return Eigen::RowVector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)); };
  const int c = 8;
  g.directions.resize(c, 3);
  g.solid_angles.resize(c);
  g.is_half.assign(c, 0);
  std::vector<Eigen::RowVector3d> pts;
  std::vector<double> w;
  g.cubature_offsets = {0};
  for (int b = 0; b < 2; ++b)
    for (int q = 0; q < 4; ++q) {
      const int cell = 4 * b + q;
      const double th = 0.5 * (bands[b] + bands[b + 1]), ph = (q + 0.5) * M_PI / 2;
      g.directions.row(cell) = dir(th, ph);
      g.solid_angles[cell] = (std::cos(bands[b]) - std::cos(bands[b + 1])) * M_PI / 2;
      if (b == 0) {
        pts.push_back(dir(th, ph));
        w.push_back(g.solid_angles[cell]);
      } else {
        g.is_half[cell] = 1;
        pts.push_back(dir(th, ph - 0.2));
        pts.push_back(dir(th, ph + 0.2));
        w.push_back(0.5 * g.solid_angles[cell]);
        w.push_back(0.5 * g.solid_angles[cell]);
      }
      g.cubature_offsets.push_back(static_cast<std::int64_t>(pts.size()));
    }
  g.cubature_points.resize(static_cast<Eigen::Index>(pts.size()), 3);
  g.cubature_weights.resize(static_cast<Eigen::Index>(w.size()));
  for (size_t i = 0; i < pts.size(); ++i) {
    g.cubature_points.row(static_cast<Eigen::Index>(i)) = pts[i];
    g.cubature_weights[static_cast<Eigen::Index>(i)] = w[i];
  }
  g.vertices = g.directions;  // any unit vectors serve: the test only needs valid vertex ids
  g.faces.resize(c, 3);
  g.neighbours.resize(c, 3);
  for (int i = 0; i < c; ++i) {
    g.faces.row(i) << i, (i + 1) % c, (i + 2) % c;
    g.neighbours.row(i) << (i + 1) % c, (i + 7) % c, i < 4 ? i + 4 : -1;
  }
  g.rotate_pi.resize(c);
  g.mirror_xz.resize(c);
  g.mirror_yz.resize(c);
  const int rot[4] = {2, 3, 0, 1}, mxz[4] = {3, 2, 1, 0}, myz[4] = {1, 0, 3, 2};
  for (int b = 0; b < 2; ++b)
    for (int q = 0; q < 4; ++q) {
      g.rotate_pi[4 * b + q] = 4 * b + rot[q];
      g.mirror_xz[4 * b + q] = 4 * b + mxz[q];
      g.mirror_yz[4 * b + q] = 4 * b + myz[q];
    }
  return g;
}

// A spectrum with distinct, non-round entries (so any transposition or reordering shows).
inline Spectrum synthetic_spectrum(int order, int channels) {
  Spectrum s;
  s.order = order;
  s.source = "model:test?order=" + std::to_string(order);
  s.filter = "none";
  s.level = 1;
  s.grid_kind = to_string(GridKind::Custom);  // the kind of synthetic_grid()
  s.gram_error = 1.25e-13;
  s.max_albedo = 0.875;  // reciprocity_violation and anisotropy_fraction stay NaN
  const int m = s.modes();
  for (int c = 0; c < channels; ++c) {
    Eigen::MatrixXd a(m, m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) a(i, j) = std::sin(1.0 + i + 0.37 * j + 2.1 * c) / (1 + i + j);
    s.channels.push_back(a);
  }
  return s;
}

// The record of a sample fit of order 2 with 3 channels (21 general modes), every field set, one noise figure
// and one standard error NaN (as the fit stores them when undefined).
inline SampleFitRecord synthetic_sample_fit() {
  SampleFitRecord f;
  f.samples = 1234;
  f.unknowns = 21;
  f.effective_rank = 20;
  f.condition = 12.5;
  f.residual_rms = {0.1, 0.2, 0.3};
  f.noise_sigma = {0.11, std::nan(""), 0.33};
  f.cv_rms = 0.25;
  f.cv_folds = 5;
  f.tikhonov = 1e-3;
  f.tikhonov_power = 1.0;
  f.order_choice = "cross-validation";
  f.tikhonov_choice = "generalized cross-validation";
  f.fallback = "none taken";
  f.solver = "QR";
  f.standard_error = Eigen::MatrixXd::Constant(3, 21, 0.01);
  f.standard_error(1, 7) = std::nan("");
  return f;
}

// Outcome of running a function in a child process.
struct ChildResult {
  bool timed_out = false;
  bool signaled = false;    // the child died from a signal (e.g. an abort inside HDF5)
  int exit_code = -1;
  std::string kind;         // "ok", "InputError", "IoError", "ArgumentError", "UnsupportedError", "ResourceError", "other"
  std::string message;      // what() of the exception
  std::string err;          // everything the child wrote to stderr
};

// Runs `f` in a forked child with `timeout_s` seconds; the exception kind and message come back via a pipe.
inline ChildResult run_in_child(const std::function<void()>& f, double timeout_s = 20.0) {
  int out[2], err[2];
  if (::pipe(out) != 0 || ::pipe(err) != 0) std::abort();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(out[0]);
    ::close(err[0]);
    ::dup2(err[1], 2);
    std::string kind = "ok", msg;
    try {
      f();
    } catch (const InputError& e) {
      kind = "InputError", msg = e.what();
    } catch (const IoError& e) {
      kind = "IoError", msg = e.what();
    } catch (const ArgumentError& e) {
      kind = "ArgumentError", msg = e.what();
    } catch (const UnsupportedError& e) {
      kind = "UnsupportedError", msg = e.what();
    } catch (const ResourceError& e) {
      kind = "ResourceError", msg = e.what();
    } catch (const std::exception& e) {
      kind = "other", msg = e.what();
    }
    const std::string payload = kind + "\n" + msg;
    if (::write(out[1], payload.data(), payload.size()) < 0) ::_exit(3);
    std::fflush(stderr);
    ::_exit(0);
  }
  ::close(out[1]);
  ::close(err[1]);
  ChildResult r;
  std::string payload;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  bool out_open = true, err_open = true;
  while (out_open || err_open) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      r.timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    pollfd fds[2] = {{out_open ? out[0] : -1, POLLIN, 0}, {err_open ? err[0] : -1, POLLIN, 0}};
    if (::poll(fds, 2, static_cast<int>(left)) <= 0) continue;
    char buf[4096];
    for (int k = 0; k < 2; ++k) {
      if (!(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(k == 0 ? out[0] : err[0], buf, sizeof buf);
      if (n <= 0) {
        (k == 0 ? out_open : err_open) = false;
      } else {
        (k == 0 ? payload : r.err).append(buf, static_cast<size_t>(n));
      }
    }
  }
  ::close(out[0]);
  ::close(err[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) r.signaled = !r.timed_out;
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  const auto nl = payload.find('\n');
  if (nl != std::string::npos) {
    r.kind = payload.substr(0, nl);
    r.message = payload.substr(nl + 1);
  }
  return r;
}

// The message of the InputError that read(file) throws, checked to be one line starting with the file;
// "" and a test failure when it throws none.
inline std::string input_error_of(const std::string& file, const std::function<void()>& read) {
  try {
    read();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(file, 0), 0u) << m;
    return m;
  }
  ADD_FAILURE() << "no InputError for " << file;
  return "";
}

}  // namespace icobrdf::test
