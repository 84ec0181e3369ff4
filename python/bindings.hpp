#pragma once
// The parts of the Python module `icobrdf` (python/module.cpp), one per class or area, each adding its
// classes and functions to the module with numpy-doc docstrings. Called in this order: a part may use the
// classes of the parts before it in its signatures.
#include <pybind11/pybind11.h>

namespace icobrdf::python {

void bind_errors(pybind11::module_& m);     // library errors -> Python exceptions (python/error_translation.cpp)
void bind_grid(pybind11::module_& m);       // Grid (python/grid_binding.cpp)
void bind_basis(pybind11::module_& m);      // basis_count, hemisphere_basis, helmholtz_modes, isotropic_modes
void bind_source(pybind11::module_& m);     // Source (Source.from_samples: arrays), models (python/source_binding.cpp)
void bind_albedo(pybind11::module_& m);     // black_sky_albedo, white_sky_albedo, albedo_nodes, white_sky_nodes; Source's
                                            // albedo methods (python/albedo_binding.cpp)
void bind_sampler(pybind11::module_& m);    // Sampler (python/sampler_binding.cpp)
void bind_sample_fit(pybind11::module_& m); // SampleFit, the record of a fit of samples (python/sample_fit_binding.cpp)
void bind_spectrum(pybind11::module_& m);   // Spectrum, fit, read_spectrum, write_spectrum, bank_materials
void bind_operators(pybind11::module_& m);  // lut, DiscreteBasis, Projection, project, reconstruct, smooth,
                                            // evaluate_coefficients (python/operator_binding.cpp)
void bind_kernel_fit(pybind11::module_& m); // sun_view_directions, kernel_fit (python/kernel_fit_binding.cpp)
void bind_bank(pybind11::module_& m);       // build_bank: a bank from a scene (python/bank_binding.cpp)

}  // namespace icobrdf::python
