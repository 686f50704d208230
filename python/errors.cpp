// svr's errors as Python exceptions with the same message: svr.Error (a RuntimeError) for what
// the library refuses (files, scene keys, values); a stopped render raises the
// KeyboardInterrupt that stopped it (render_call.h), never svr.Cancelled on its own.

#include "python/bindings.h"
#include "base/error.h"

namespace svr::python {

void bindErrors(py::module_& m) {
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.doc() = "An input svr refuses: the message names the file, key and value.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      error(e.what());
    }
  });
}

}  // namespace svr::python
