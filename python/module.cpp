// `import svr` (docs/python.md): the library's scenes, volumes from numpy, renders whose
// light-independent images are numpy views, relighting, comparisons and the spectrum library.
// python/svr/__init__.py re-exports this extension (_svr) as the package.

#include <pybind11/pybind11.h>

#include <map>
#include <mutex>
#include <nlohmann/json.hpp>

#include "python/bindings.h"
#include "base/data_dir.h"
#include "svr/svr.h"

namespace svr::python {

std::shared_ptr<const SessionSpectra> spectraFor(const std::string& data_dir) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const SessionSpectra>> loaded;
  const std::string dir = data_dir.empty() ? defaultDataDir() : data_dir;
  const std::lock_guard lock(mutex);
  auto& entry = loaded[dir];
  if (!entry) entry = std::make_shared<const SessionSpectra>(dir);
  return entry;
}

py::object jsonToPython(const std::string& json_text) {
  return py::module_::import("json").attr("loads")(json_text);
}

}  // namespace svr::python

PYBIND11_MODULE(_svr, m) {
  namespace sp = svr::python;
  m.doc() = "svr: spectral volume rendering (Bergner et al. 2002) from Python; see docs/python.md";
  m.attr("__version__") = SVR_VERSION;  // svr::version() lives in libsvr, which this does not link
  sp::bindErrors(m);
  sp::bindLibrary(m);
  sp::bindVolume(m);
  sp::bindScene(m);
  sp::bindImage(m);
  sp::bindCompare(m);
}
