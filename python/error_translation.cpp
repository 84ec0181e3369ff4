// Library errors (icobrdf/core/support/error.hpp) as Python exceptions: ArgumentError -> ValueError,
// IoError -> OSError, ResourceError -> MemoryError, InputError and UnsupportedError -> RuntimeError; the
// message is the library's one line.
#include <pybind11/pybind11.h>

#include "icobrdf/core/support/error.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

void bind_errors(pybind11::module_&) {
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ArgumentError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const ResourceError& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    } catch (const UnsupportedError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
}

}  // namespace icobrdf::python
