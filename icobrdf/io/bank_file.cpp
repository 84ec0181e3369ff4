#include "icobrdf/io/bank_file.hpp"

#include <cstdlib>
#include <ctime>
#include <map>
#include <set>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/finite_values.hpp"
#include "icobrdf/core/support/text.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/bank_format.hpp"
#include "icobrdf/io/output_path.hpp"

namespace icobrdf {

namespace {

// Deepest group nesting accepted under /basis ("<order>/<name>" needs 2).
constexpr int kMaxBasisDepth = 4;
// Largest rank of a basis array (matrices and index tables need 2, stacked matrices 3).
constexpr size_t kMaxBasisRank = 3;

std::string now_iso8601() {
  if (const char* e = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long t = std::strtoll(e, &end, 10);
    if (end && *end == '\0' && end != e && t >= 0) return iso8601_utc(t);
  }
  return iso8601_utc(static_cast<long long>(std::time(nullptr)));
}

// The checks of one material before it is written: a valid name, not in `names` yet (added), finite values.
void check_material(const std::string& path, const MaterialRecord& m, std::set<std::string>& names) {
  validate_material_name(m.name);
  require_finite_material(path, m);
  if (!names.insert(m.name).second) throw ArgumentError("cannot write bank: material name '" + m.name + "' appears twice");
}

void check_contents(const std::string& path, const BankContents& c) {
  std::set<std::string> names;
  for (const auto& m : c.materials) check_material(path, m, names);
  std::set<std::string> paths;
  for (const auto& b : c.basis) {
    const auto parts = split_at(b.path, '/');
    if (parts.size() > static_cast<size_t>(kMaxBasisDepth))
      throw ArgumentError("cannot write bank: basis array '" + b.path + "' nests deeper than " + std::to_string(kMaxBasisDepth));
    for (const auto& p : parts) {
      const std::string problem = material_name_problem(p);
      if (!problem.empty()) throw ArgumentError("cannot write bank: basis array path '" + b.path + "': " + problem);
    }
    if (b.shape.empty() || b.shape.size() > kMaxBasisRank)
      throw ArgumentError("cannot write bank: basis array '" + b.path + "': expected rank 1 to " + std::to_string(kMaxBasisRank) +
                          ", found " + std::to_string(b.shape.size()));
    std::uint64_t n = 1;
    for (auto d : b.shape) n *= d;
    const bool v = b.values.size() == n && b.indices.empty(), i = b.indices.size() == n && b.values.empty();
    if (!v && !i)
      throw ArgumentError("cannot write bank: basis array '" + b.path + "': expected exactly one of values / indices with " +
                          std::to_string(n) + " entries (shape " + h5::shape_text(b.shape) + "), found " +
                          std::to_string(b.values.size()) + " / " + std::to_string(b.indices.size()));
    require_finite(Eigen::Map<const Eigen::VectorXd>(b.values.data(), static_cast<Eigen::Index>(b.values.size())),
                   path + ": basis array '" + b.path + "'", "the operator");
    if (!paths.insert(b.path).second) throw ArgumentError("cannot write bank: basis array '" + b.path + "' appears twice");
  }
  for (const auto& p : paths)
    for (const auto& q : paths)
      if (q.size() > p.size() && q.compare(0, p.size() + 1, p + "/") == 0)
        throw ArgumentError("cannot write bank: basis array '" + p + "' is also a group of '" + q + "'");
}

void write_basis(h5::Group& root, const std::vector<BasisArray>& basis) {
  if (basis.empty()) return;
  std::map<std::string, h5::Group> groups;
  groups.emplace("", root.create_group(bank_format::kBasisGroup));
  for (const auto& b : basis) {
    const auto parts = split_at(b.path, '/');
    std::string prefix;
    for (size_t k = 0; k + 1 < parts.size(); ++k) {
      const std::string next = prefix.empty() ? parts[k] : prefix + "/" + parts[k];
      if (!groups.count(next)) groups.emplace(next, groups.at(prefix).create_group(parts[k]));
      prefix = next;
    }
    h5::Group& g = groups.at(prefix);
    if (!b.values.empty() || b.indices.empty())
      g.write(parts.back(), b.values.data(), b.shape, b.unit, b.description);
    else
      g.write(parts.back(), b.indices.data(), b.shape, b.unit, b.description);
  }
}

void read_basis(const h5::Group& g, const std::string& prefix, int depth, const h5::ReadLimits& lim, std::vector<BasisArray>* out) {
  if (depth > kMaxBasisDepth) g.fail(g.path(), "expected at most " + std::to_string(kMaxBasisDepth) + " nested groups under /basis");
  for (const auto& name : g.children()) {
    const std::string problem = material_name_problem(name);
    if (!problem.empty()) g.fail(g.child_path(name), "invalid name: " + problem);
    const std::string path = prefix.empty() ? name : prefix + "/" + name;
    if (g.is_group(name)) {
      read_basis(g.open_group(name), path, depth + 1, lim, out);
      continue;
    }
    BasisArray b;
    b.path = path;
    const h5::Type t = g.dataset_type(name, lim);
    const h5::Shape shape = g.dataset_shape(name, lim);
    if (shape.empty() || shape.size() > kMaxBasisRank)
      g.fail(g.child_path(name), "expected rank 1 to " + std::to_string(kMaxBasisRank) + ", found " + std::to_string(shape.size()));
    const h5::ShapePattern pattern(shape.begin(), shape.end());
    if (t == h5::Type::float64) {
      auto a = g.read<double>(name, pattern, lim);
      for (double x : a.data)
        if (!std::isfinite(x)) g.fail(g.child_path(name), "expected finite values, found " + std::to_string(x));
      b.values = std::move(a.data);
    } else if (t == h5::Type::int32) {
      b.indices = g.read<std::int32_t>(name, pattern, lim).data;
    } else {
      g.fail(g.child_path(name), std::string("expected float64 or int32, found ") + h5::type_name(t));
    }
    b.shape = shape;
    const h5::Group attrs = g.attributes_of(name);
    b.unit = attrs.attr_string("unit");
    if (attrs.has_attr("description")) b.description = attrs.attr_string("description");
    out->push_back(std::move(b));
  }
}

// Most digits of a version part: any such number fits an int.
constexpr size_t kMaxVersionDigits = 9;

// "MAJOR.MINOR" with decimal digits (at most kMaxVersionDigits each); false otherwise.
bool parse_version(const std::string& v, int* major, int* minor) {
  const auto dot = v.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == v.size() || dot > kMaxVersionDigits ||
      v.size() - dot - 1 > kMaxVersionDigits)
    return false;
  for (size_t i = 0; i < v.size(); ++i)
    if (i != dot && !(v[i] >= '0' && v[i] <= '9')) return false;
  *major = std::stoi(v.substr(0, dot));
  *minor = std::stoi(v.substr(dot + 1));
  return true;
}

h5::ReadLimits limits_of(const ReadOptions& o) { return h5::ReadLimits{o.max_dataset_bytes}; }

std::optional<GridSummary> grid_summary(const h5::Group& root) {
  if (!root.has(bank_format::kGridGroup)) return std::nullopt;
  return read_grid_summary(root.open_group(bank_format::kGridGroup));
}

}  // namespace

BasisArray BasisArray::matrix(const std::string& path, const Eigen::MatrixXd& m, const std::string& unit,
                              const std::string& description) {
  BasisArray b;
  b.path = path;
  b.shape = {static_cast<std::uint64_t>(m.rows()), static_cast<std::uint64_t>(m.cols())};
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
  b.values.assign(r.data(), r.data() + r.size());
  b.unit = unit;
  b.description = description;
  return b;
}

std::string iso8601_utc(long long seconds) {
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

namespace {

// The checks write_bank makes before anything is written; ArgumentError naming `path`.
void check_bank_contents(const std::string& path, const BankContents& c) {
  h5::init();
  check_contents(path, c);
  if (c.grid) {
    try {
      validate(*c.grid);
    } catch (const std::invalid_argument& e) {
      throw ArgumentError(std::string("cannot write bank: ") + e.what());
    }
  }
}

// A bank is written in three parts, in this order: the materials group and each material (write_bank's
// order, or as a BankWriter gets them), then the grid and the operators, then the root attributes; the
// `complete` attribute last of all (WriteFile::finish).
}  // namespace

// (Outside the anonymous namespace: BankWriter::State holds one.)
struct BankRootFlags {
  bool lobes = false, fits = false;  // some material has a lobe / a sample-fit record (format_version)
  bool compact = false;              // some lobe stores float32 / integer / shared factors (format 4)
  void note(const MaterialRecord& m) {
    lobes = lobes || m.lobe.has_value();
    compact = compact || (m.lobe && (m.lobe->shared() || m.lobe->precision != FactorPrecision::Float64));
    fits = fits || sample_fit_record_matches(m.spectrum);
  }
};

namespace {

void write_bank_rest(h5::Group& root, const BankContents& c, const BankRootFlags& flags) {
  if (c.grid) write_grid(root, *c.grid, bank_format::kGridGroup);
  write_basis(root, c.basis);
  const std::string created = c.created.empty() ? now_iso8601() : c.created;
  root.set_attr("format", bank_format::kName);
  root.set_attr("format_version", flags.compact ? (flags.fits ? bank_format::kVersionCompactLobesSampleFit : bank_format::kVersionCompactLobes)
                                  : flags.lobes ? (flags.fits ? bank_format::kVersionSampleFit : bank_format::kVersion)
                                                : (flags.fits ? bank_format::kVersionModesOnlySampleFit : bank_format::kVersionModesOnly));
  root.set_attr("creator", std::string("icobrdf ") + ICOBRDF_VERSION);
  root.set_attr("created", created);
  root.set_attr("conventions", bank_format::kConventions);
  root.set_attr("axis_order", bank_format::kAxisOrder);
}

// Everything of a bank but the final `complete` attribute (WriteFile::finish writes it).
void write_bank_content(h5::WriteFile& f, const BankContents& c) {
  h5::Group root = f.root();
  h5::Group mats = root.create_group(bank_format::kMaterialsGroup);
  BankRootFlags flags;
  for (const auto& m : c.materials) {
    write_material(mats, m);
    flags.note(m);
    write_fault_point("bank:material");
  }
  write_bank_rest(root, c, flags);
}

// The checks of the root attributes (format, major version, complete) that open_bank makes.
h5::ReadFile checked_bank(h5::ReadFile f);

// A whole bank from an open, checked file.
BankContents read_bank_content(const h5::ReadFile& f, const ReadOptions& o);

}  // namespace

void write_bank(const std::string& path, const BankContents& c) {
  check_bank_contents(path, c);
  atomic_write(path, [&](const std::string& temp) {
    h5::WriteFile f = h5::WriteFile::create(temp, path);
    write_bank_content(f, c);
    write_fault_point("bank:before-complete");
    f.finish();
  });
}

struct BankWriter::State {
  explicit State(const std::string& p) : file(p), h5(h5::WriteFile::create(file.temp_path(), p)) {
    root.emplace(h5.root());
    materials.emplace(root->create_group(bank_format::kMaterialsGroup));
  }
  AtomicFile file;
  h5::WriteFile h5;
  std::optional<h5::Group> root, materials;  // closed before the file is
  std::set<std::string> names;
  BankRootFlags flags;
};

BankWriter::BankWriter(const std::string& path) : path_(path) {
  h5::init();
  s_ = std::make_unique<State>(path);
}

BankWriter::~BankWriter() = default;

void BankWriter::add(const MaterialRecord& m) {
  if (!s_) throw ArgumentError("cannot write bank: the writer of " + quoted_text(path_) + " has finished");
  check_material(path_, m, s_->names);
  write_material(*s_->materials, m);
  s_->flags.note(m);
  write_fault_point("bank:writer-material");
}

void BankWriter::finish(const BankContents& rest) {
  if (!s_) throw ArgumentError("cannot write bank: the writer of " + quoted_text(path_) + " has finished");
  if (!rest.materials.empty()) throw ArgumentError("cannot write bank: BankWriter::finish takes the grid and operators only, found materials");
  check_bank_contents(path_, rest);
  write_bank_rest(*s_->root, rest, s_->flags);
  write_fault_point("bank:before-complete");
  s_->materials.reset();
  s_->root.reset();
  s_->h5.finish();
  s_->file.commit();
  s_.reset();
}

std::string bank_image(const BankContents& c, const std::string& name) {
  check_bank_contents(name, c);
  h5::WriteFile f = h5::WriteFile::create_in_memory(name);
  write_bank_content(f, c);
  return f.finish_image();
}

BankContents read_bank_image(const std::string& bytes, const std::string& name, const ReadOptions& o) {
  return read_bank_content(checked_bank(h5::ReadFile::open_image(bytes, name)), o);
}

h5::ReadFile open_bank(const std::string& path) { return checked_bank(h5::ReadFile::open(path)); }

namespace {

h5::ReadFile checked_bank(h5::ReadFile f) {
  const h5::Group root = f.root();
  const std::string format = root.attr_string("format");
  if (format != bank_format::kName)
    root.fail("/", std::string("attribute format: expected '") + bank_format::kName + "', found '" + format + "'");
  const std::string version = root.attr_string("format_version");
  int major = 0, minor = 0;
  if (!parse_version(version, &major, &minor))
    root.fail("/", "attribute format_version: expected MAJOR.MINOR, found '" + version + "'");
  if (major > bank_format::kMajor)
    root.fail("/", "format_version " + version + " is newer than this reader: expected major version " +
                       std::to_string(bank_format::kOldestMajor) + " to " + std::to_string(bank_format::kMajor) +
                       "; upgrade icobrdf to read it");
  if (major < bank_format::kOldestMajor)
    root.fail("/", "format_version " + version + " is older than this reader supports: expected major version " +
                       std::to_string(bank_format::kOldestMajor) + " to " + std::to_string(bank_format::kMajor));
  if (!root.has_attr("complete"))
    root.fail("/", "expected attribute complete = 1, found none (the write did not finish)");
  if (!root.attr_bool("complete")) root.fail("/", "expected attribute complete = 1, found 0 (the write did not finish)");
  return f;
}

BankContents read_bank_content(const h5::ReadFile& f, const ReadOptions& o) {
  const h5::Group root = f.root();
  root.check_links();
  const h5::ReadLimits lim = limits_of(o);
  BankContents b;
  b.created = root.attr_string("created");
  b.creator = root.attr_string("creator");
  b.format_version = root.attr_string("format_version");
  std::optional<GridSummary> gs;
  if (root.has(bank_format::kGridGroup)) {
    const h5::Group g = root.open_group(bank_format::kGridGroup);
    b.grid = read_grid(g, lim);
    gs = read_grid_summary(g);
  }
  if (root.has(bank_format::kBasisGroup)) read_basis(root.open_group(bank_format::kBasisGroup), "", 1, lim, &b.basis);
  const h5::Group mats = root.open_group(bank_format::kMaterialsGroup);
  for (const auto& name : mats.children()) b.materials.push_back(read_material(mats, name, lim, o.read_luts, gs));
  return b;
}

}  // namespace

BankContents read_bank(const std::string& path, const ReadOptions& o) { return read_bank_content(open_bank(path), o); }

MaterialRecord read_bank_material(const std::string& path, const std::string& name, const ReadOptions& o) {
  const h5::ReadFile f = open_bank(path);
  const h5::Group root = f.root();
  root.check_links();
  const h5::Group mats = root.open_group(bank_format::kMaterialsGroup);
  std::string which = name;
  if (which.empty()) {
    const auto names = mats.children();
    if (names.empty()) mats.fail(mats.path(), "expected at least one material, found none");
    which = names.front();
  } else if (!mats.has(which)) {
    mats.fail(mats.child_path(which), "no such material");
  }
  return read_material(mats, which, limits_of(o), o.read_luts, grid_summary(root));
}

void extract_bank_material(const std::string& ref, const std::string& output) {
  if (ref.find('#') == std::string::npos) throw ArgumentError("bank extract: expected BANK.h5#MATERIAL, found '" + ref + "'");
  check_output_path(output, {ref});
  const auto [path, name] = split_material_ref(ref);
  BankContents b;
  b.materials.push_back(read_bank_material(path, name));
  write_bank(output, b);
}

std::vector<std::string> bank_material_names(const std::string& path) {
  const h5::ReadFile f = open_bank(path);
  return f.root().open_group(bank_format::kMaterialsGroup).children();
}

MaterialRef split_material_ref(const std::string& text) {
  const auto hash = text.rfind('#');
  if (hash == std::string::npos) return {text, ""};
  return {text.substr(0, hash), text.substr(hash + 1)};
}

}  // namespace icobrdf
