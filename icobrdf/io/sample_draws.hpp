#pragma once
// Importance-sampled reflected directions of a SOURCE for one incident direction (`icobrdf sample`), drawn
// with a seeded 64-bit Mersenne twister (std::mt19937_64), and their CSV form.
#include <cstdint>
#include <string>

#include "icobrdf/io/material_sampler.hpp"

namespace icobrdf {

// `n` draws of `sampler` for the incident direction `wi` (unit, z up): the uniform numbers u1, u2 of draw i are
// the (2i)-th and (2i+1)-th of std::uniform_real_distribution(0, 1) on std::mt19937_64(seed), so that a seed
// gives the same draws on every platform of one standard library.
MaterialSamples draw_material_samples(const MaterialSampler& sampler, const Eigen::Vector3d& wi, long long n, std::uint64_t seed);

// CSV: header theta_r,phi_r,pdf,weight (one weight column per channel, named after the source's channels), then
// one line per draw: angles in degrees, pdf in 1/sr, weight f cos(theta_r) / pdf; shortest round-trip decimals.
std::string material_samples_csv(const MaterialSampler& sampler, const MaterialSamples& samples);

}  // namespace icobrdf
