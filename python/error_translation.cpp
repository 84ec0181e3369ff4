// Library errors (icobrdf/core/support/error.hpp) as Python exceptions: ArgumentError -> ValueError,
// IoError -> OSError, ResourceError -> MemoryError, InputError and UnsupportedError -> RuntimeError; the
// message is the library's one line, its bytes outside well-formed UTF-8 escaped (icobrdf/io/utf8_text.hpp).
// And the memory budget the calls hold themselves to before they allocate
// (icobrdf/core/support/memory_budget.hpp): set_memory_budget, available_memory.
#include <pybind11/pybind11.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/io/utf8_text.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

void bind_errors(pybind11::module_& m) {
  m.def("set_memory_budget", [](const pybind11::object& size) {
          set_memory_budget(pybind11::isinstance<pybind11::str>(size) ? parse_byte_size(size.cast<std::string>()) : size.cast<double>());
        }, pybind11::arg("size"), R"doc(Sets the memory the calls may use, as the program's --memory-budget.

Parameters
----------
size : str or float
    "8G", "512MB", ... or bytes; 0 restores measuring (MemAvailable, cgroup limit, RLIMIT_AS).

A call whose estimate exceeds it raises MemoryError before it allocates (lut, DiscreteBasis, Grid.equal_area,
Sampler, fit, reading banks).
)doc");
  m.def("available_memory", [] { return available_memory().bytes; }, R"doc(The memory a call may use now.

Returns
-------
float
    Bytes: the budget of set_memory_budget, or the smallest of MemAvailable, the cgroup limit and RLIMIT_AS.
)doc");
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ArgumentError& e) {
      PyErr_SetString(PyExc_ValueError, valid_utf8_text(e.what()).c_str());
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, valid_utf8_text(e.what()).c_str());
    } catch (const ResourceError& e) {
      PyErr_SetString(PyExc_MemoryError, valid_utf8_text(e.what()).c_str());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_RuntimeError, valid_utf8_text(e.what()).c_str());
    } catch (const UnsupportedError& e) {
      PyErr_SetString(PyExc_RuntimeError, valid_utf8_text(e.what()).c_str());
    }
  });
}

}  // namespace icobrdf::python
