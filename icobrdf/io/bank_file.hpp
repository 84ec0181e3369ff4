#pragma once
// Banks: whole icobrdf HDF5 files (schema "icobrdf-bank", icobrdf/io/bank_format.hpp, docs/file-format.md).
//
//   /                 attributes format, format_version, creator, created, conventions, axis_order, complete
//   /grid             optional: the Grid the LUTs and spectra were computed on (icobrdf/io/grid_file.hpp)
//   /basis/...        optional: named operator arrays (index tables, B, Gram, P, S, filter weights)
//   /materials/<name> one group per material (icobrdf/io/spectrum_file.hpp)
//
// write_bank is atomic (icobrdf/io/atomic_write.hpp): the path holds either its previous content or the complete
// new bank; `complete` = 1 is the last attribute written. read_bank validates everything it reads
// (h5::Group) and refuses files whose format is not icobrdf-bank, whose major version is not ours, or that
// lack complete = 1. Banks are trusted input beyond these checks: HDF5 itself parses the file structure.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/io/h5_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf {

// One array under /basis: `path` is relative to /basis ("4/B"), each component a valid material-style name.
// Exactly one of `values` (float64) or `indices` (int32) holds product(shape) entries, row-major.
struct BasisArray {
  std::string path;
  h5::Shape shape;
  std::vector<double> values;
  std::vector<std::int32_t> indices;
  std::string unit;         // "1", "sr", "1/sr", "rad", "index", ...
  std::string description;  // free text, stored as the dataset's description attribute

  static BasisArray matrix(const std::string& path, const Eigen::MatrixXd& m, const std::string& unit,
                           const std::string& description);
};

struct BankContents {
  std::optional<Grid> grid;
  std::vector<MaterialRecord> materials;  // written in this order; read back in name order
  std::vector<BasisArray> basis;          // read back in path order
  // Root metadata. On write: `created` empty means now (or SOURCE_DATE_EPOCH when set, for reproducible
  // files); `creator` and `format_version` are ignored. On read: the stored values.
  std::string created;
  std::string creator;
  std::string format_version;
};

struct ReadOptions {
  std::uint64_t max_dataset_bytes = h5::kDefaultMaxDatasetBytes;  // refuse any larger dataset before allocating
  bool read_luts = true;                                          // false: validate LUT metadata only
};

// ArgumentError for invalid contents (names, shapes, NaN); IoError when the file system refuses.
void write_bank(const std::string& path, const BankContents& contents);

// InputError for anything malformed, IoError when the file cannot be opened.
BankContents read_bank(const std::string& path, const ReadOptions& options = {});

// A bank written as it is built (`bank build`, icobrdf/pipeline/bank_builder.hpp): the constructor creates
// the temporary beside `path` (icobrdf/io/atomic_write.hpp AtomicFile); add() writes one material at once,
// with write_bank's checks for it (name, finite values, no name twice); finish() writes the grid, the
// operators and the root attributes of `rest` (whose materials must be empty), then `complete`, and puts
// the file in place. Destroyed before finish() (an error, an interrupted build), it leaves `path` untouched
// and removes the temporary. The same contents give the same bytes as write_bank. Not thread-safe. Fault
// point (set_write_fault_hook): "bank:writer-material" after each material added.
class BankWriter {
 public:
  explicit BankWriter(const std::string& path);
  ~BankWriter();
  BankWriter(const BankWriter&) = delete;
  BankWriter& operator=(const BankWriter&) = delete;
  void add(const MaterialRecord& material);
  void finish(const BankContents& rest);

 private:
  struct State;
  std::string path_;
  std::unique_ptr<State> s_;  // null once finished
};

// A bank as the bytes of its file, made and read in memory (no file system; e.g. to send a finished material
// to another process, icobrdf/cluster/distributed_bank.hpp). The same checks and errors as write_bank and
// read_bank; `name` stands for the file in messages.
std::string bank_image(const BankContents& contents, const std::string& name);
BankContents read_bank_image(const std::string& bytes, const std::string& name, const ReadOptions& options = {});

// One material (and no other arrays); `name` empty = the first material in name order.
MaterialRecord read_bank_material(const std::string& path, const std::string& name, const ReadOptions& options = {});

// `bank extract`: the material of "BANK.h5#MATERIAL" into a bank of its own at `output`. The output path is
// checked before anything is read (icobrdf/io/output_path.hpp): an output that is the bank itself is refused
// (ArgumentError), as is a reference without '#MATERIAL'.
void extract_bank_material(const std::string& ref, const std::string& output);

// Names of the materials, in name order (validates the root only).
std::vector<std::string> bank_material_names(const std::string& path);

// Opens a bank and checks the root attributes (format, major version, complete). Throws as read_bank.
h5::ReadFile open_bank(const std::string& path);

// "FILE.h5#MATERIAL" or "FILE.h5": the file and the material name (empty when there is no '#').
struct MaterialRef {
  std::string path, name;
};
MaterialRef split_material_ref(const std::string& text);

// UTC ISO 8601 text of a time ("2026-11-22T04:49:30Z").
std::string iso8601_utc(long long seconds_since_epoch);

}  // namespace icobrdf
