// Library errors (icobrdf/core/support/error.hpp) as Python exceptions: ArgumentError -> ValueError,
// IoError -> OSError, ResourceError -> MemoryError, InputError and UnsupportedError -> RuntimeError; the
// message is the library's one line, its bytes outside well-formed UTF-8 escaped (icobrdf/io/utf8_text.hpp).
#include <pybind11/pybind11.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/utf8_text.hpp"
#include "python/bindings.hpp"

namespace icobrdf::python {

void bind_errors(pybind11::module_&) {
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
