#pragma once
// Importance-sampled reflected directions of a SOURCE for one incident direction (`icobrdf sample`), drawn
// with a seeded 64-bit Mersenne twister (std::mt19937_64), and their CSV form.
//
// Memory: the draws are made and written in blocks of kSampleDrawBlock, so that `n` costs time, not memory
// (1e8 draws once took 10.9 GB as one array and one string). A run writes nothing unless every draw
// succeeded: when n exceeds one block, every block is drawn, weighed (f evaluated once per draw) and
// checked first, its weights kept in an unnamed temporary file of $TMPDIR (8 bytes per draw and channel:
// 2.4 GB for 1e8 draws of 3 channels); then the directions are drawn again from the same seed (the same
// numbers, bit for bit; no f evaluated) and written with the kept weights. Before, f was evaluated twice
// per draw. Progress lines "drawing" and "writing" (icobrdf/core/support/progress.hpp) for long runs.
#include <cstdint>
#include <iosfwd>
#include <string>

#include "icobrdf/io/material_sampler.hpp"

namespace icobrdf {

// Draws per block of write_material_samples_csv: about 10 MB of directions, weights and text.
inline constexpr long long kSampleDrawBlock = 1 << 16;

// `n` draws of `sampler` for the incident direction `wi` (unit, z up) as CSV, written to `out` block by block:
// header theta_r,phi_r,pdf,weight (one weight column per channel, named after the source's channels), then one
// line per draw: angles in degrees, pdf in 1/sr, weight f cos(theta_r) / pdf; shortest round-trip decimals.
// The uniform numbers u1, u2 of draw i are the (2i)-th and (2i+1)-th of std::uniform_real_distribution(0, 1)
// on std::mt19937_64(seed), so that a seed gives the same draws on every platform of one standard library,
// whatever the blocks. UnsupportedError (nothing written) when a weight is not finite; ResourceError (before
// any draw, nothing written) when the temporary folder has less free space than the weights need
// (icobrdf/io/disk_space.hpp); IoError (nothing written) when their temporary file cannot be written.
// Returns false when `out` failed.
bool write_material_samples_csv(std::ostream& out, const MaterialSampler& sampler, const Eigen::Vector3d& wi, long long n,
                                std::uint64_t seed);

}  // namespace icobrdf
