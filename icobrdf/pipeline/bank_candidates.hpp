#pragma once
// The error-against-bytes record of a material's bank build: every point its representations reached
// (icobrdf/pipeline/material_problem.hpp CandidatePoint: each candidate, each order of the modes' search, each
// grid of a lobe's ladder), stored with the material as the text label `candidates` of its `choice` group
// (icobrdf/io/spectrum_file.hpp MaterialRecord::labels; docs/file-format.md), format version 1, one line:
//
//   icobrdf-candidates 1; representation,bytes,error_l2; modes,60,0.5; modes,120,0.21; half-angle,16933,0.0046
//
// error_l2 is the relative L2 error over the held-out pairs in the material's metric, with 17 significant digits
// (exact round trip). Points with the same representation and bytes keep the lowest error; at most
// kMaxCandidatePoints points are kept (the fewest bytes first), so the label stays far below HDF5's 64 KiB
// attribute limit. Banks built before this record have no such label: their list is empty.
#include <string>
#include <vector>

#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/material_problem.hpp"

namespace icobrdf {

inline constexpr const char* kCandidatesLabel = "candidates";
inline constexpr int kCandidatesVersion = 1;
inline constexpr std::size_t kMaxCandidatePoints = 600;  // about 45 bytes each: < 30 KB of text

// The label text of `points` (sorted by representation, then bytes; duplicates merged as above).
std::string candidates_text(std::vector<CandidatePoint> points);
// The points of a label; InputError naming `where` for a malformed text or a newer version.
std::vector<CandidatePoint> parse_candidates(const std::string& text, const std::string& where);

// What `plot bytes` draws of one bank material: its points, its target and the candidate the build chose.
struct BankMaterialCandidates {
  std::string name;
  std::vector<CandidatePoint> points;  // empty for banks built before the record
  double target = 0.0;
  CandidatePoint chosen;               // the representation, bytes and error the bank stores
};
// The material of "BANK.h5#MATERIAL" (or of a bank holding one material). ArgumentError when the bank holds
// several and none is named; InputError when the material was not made by a bank build (no `choice` figures).
BankMaterialCandidates read_bank_candidates(const std::string& text);

}  // namespace icobrdf
