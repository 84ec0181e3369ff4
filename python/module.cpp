// The Python module `icobrdf` (pybind11): the library's matrix BRDF operations on numpy arrays.
//
// Conventions are the library's: directions are unit vectors ((n, 3) float64 arrays, +z the normal,
// z >= 0), w_i points toward the light; f is in 1/sr; coefficient matrices are M x M, M = (N+1)(N+2)/2, in
// ANSI order (docs/api.md). Arrays passed in are copied into the library's types (row-major n x 3 for
// directions); arrays returned are new numpy arrays owned by Python. Long calls release the GIL.
// A direction may also be one 1-D array of 3 values, paired with every row of the other argument; directions
// that are not unit vectors are refused (ValueError). Errors map to Python exceptions: ValueError (bad
// arguments), OSError (files), RuntimeError (input data, unsupported requests), MemoryError (resources). Each class or area is bound in its own file
// (python/bindings.hpp).
#include <pybind11/pybind11.h>

#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "python/bindings.hpp"

PYBIND11_MODULE(icobrdf, m) {
  using namespace icobrdf::python;
  m.doc() = "icobrdf: BRDFs as exact linear algebra on an equal-area icosahedral hemisphere tessellation";
  m.attr("__version__") = ICOBRDF_VERSION;
  icobrdf::set_default_dense_kernels(&icobrdf::fit_dense_kernels());  // the sample fits' kernels, as in the icobrdf program
  bind_errors(m);
  bind_grid(m);
  bind_basis(m);
  bind_source(m);
  bind_albedo(m);
  bind_sampler(m);
  bind_sample_fit(m);
  bind_spectrum(m);
  bind_operators(m);
  bind_kernel_fit(m);
  bind_bank(m);
}
