#pragma once
// `mpirun -np R icobrdf bank build SCENE.toml -o BANK.h5`: the materials of a scene spread over R ranks.
//
// Scheduling: a work queue on rank 0, dynamic because material costs differ by 1000x. Rank 0 keeps the list
// of materials not yet handed out; a helper thread of rank 0 answers each request of another rank with the
// next index (or "done"), while rank 0's main thread takes indices from the same list and fits them itself.
// A rank asks for its next materials before it finishes the current one (materials_ahead below).
// Each rank fits whole materials with the one-process code (icobrdf/pipeline/bank_builder.hpp, MaterialFitter,
// its OpenMP threads included).
//
// What moves: rank 0 -> rank r: one 8-byte index per material. Rank r -> rank 0: per material an 11-byte
// header and the finished record in the exact binary form of icobrdf/io/record_wire.hpp (every field, doubles
// as their bytes; 4 us to make and read an order-6 record, where a one-material HDF5 image took 0.9 ms), or the failure's
// message. docs/cluster.md gives the sizes. Rank 0 checks and stores a received record as it does its own.
//
// Writing: rank 0 alone, with the one-process writer (BankCollector): it checks the output paths and reads
// the resume file before any rank starts, checkpoints OUTPUT.partial as results arrive (--resume works as in
// one process; materials in the resume file are never handed out), and writes the bank as records arrive,
// in scene order, into a temporary renamed into place at the end (BankWriter), so that the bank is
// byte-identical to a one-process build up to the `seconds` figures.
//
// Failures: a material that fails on any rank fails the build (no bank; the others are finished and kept for
// --resume) and its report names the rank (MaterialReport::rank). A rank that dies makes mpirun end the
// job: mpirun names the dead rank and sends SIGTERM to the others, and rank 0 prints at once one line naming
// the material each rank was fitting. Progress lines come from rank 0 only (options.progress is called
// there, from either of its threads, one line at a time).
//
// Call on every rank of `cluster` with the same scene; the other ranks return an empty result
// (`worker` = true) once rank 0 has no more work for them.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "icobrdf/cluster/cluster.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"

namespace icobrdf {

// Look-ahead: a rank holds, beside the material it fits, materials_ahead(its mean fitting time so far)
// more, so that the round trip to rank 0 (a poll interval, and the wake-up of rank 0's helper thread on a
// busy node: a few milliseconds) never leaves it idle. That covers kAheadSeconds of fitting, at least one
// material (also before any was fitted: a NaN, zero or negative mean) and at most kMaxAhead. At the end of a
// build a rank so holds at most about kAheadSeconds of work beyond its current material (or one expensive
// material) that another rank might have done sooner.
inline constexpr double kAheadSeconds = 0.02;
inline constexpr int kMaxAhead = 16;
inline int materials_ahead(double mean_fit_seconds) {
  if (!(mean_fit_seconds > 0.0)) return 1;
  return static_cast<int>(std::clamp(std::ceil(kAheadSeconds / mean_fit_seconds), 1.0, static_cast<double>(kMaxAhead)));
}

struct DistributedBankResult {
  BankBuildResult build;  // rank 0: the build's result, as build_bank's
  bool worker = false;    // ranks other than 0: nothing to report
};

DistributedBankResult build_bank_distributed(const Scene& scene, const BankBuildOptions& options, Cluster& cluster);

// The scene at `path`, read on every rank of `cluster`: a rank that cannot read it rethrows its own error; on
// the others rank 0 throws InputError naming the lowest failed rank, and the rest get nullopt (they end
// quietly: the failed rank says why).
std::optional<Scene> read_scene_on_every_rank(const std::string& path, Cluster& cluster);

}  // namespace icobrdf
