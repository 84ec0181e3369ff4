#pragma once
// The SOURCE behind the Python classes `icobrdf.Source` and `icobrdf.Sampler`: opened once
// (icobrdf/io/brdf_source.hpp open_source) and shared, so a Sampler keeps its source alive.
#include <memory>

#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_sampler.hpp"
#include "python/array_arguments.hpp"

namespace icobrdf::python {

struct PySource {
  std::shared_ptr<BrdfSource> source;
};

// Importance sampling from a source: the MaterialSampler plus the source it keeps alive.
struct PySampler {
  MaterialSampler sampler;
};

// f [1/sr] of `s` at the n pairs (wi, wr): n x channels, chunk by chunk with the GIL released.
inline Eigen::MatrixXd eval_source(const BrdfSource& s, const DirArray& wi, const DirArray& wr) {
  return eval_chunked(wi, wr, s.channels(), [&s](const RowMatrix3d& a, const RowMatrix3d& b) { return s.eval(a, b); });
}

}  // namespace icobrdf::python
