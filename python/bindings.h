#pragma once
// The Python module's parts (python/module.cpp registers them). Each binds one concept of the
// library; none holds a second implementation of anything the library does.

#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "harness/render_session.h"

namespace svr::python {

namespace py = pybind11;

// The spectra of a data folder ("" = svr's own), loaded once per process and folder.
std::shared_ptr<const SessionSpectra> spectraFor(const std::string& data_dir);

// A scene as the module holds it: loaded and checked, its volume shared between copies.
struct PyScene {
  std::shared_ptr<const SessionSpectra> spectra;
  std::shared_ptr<const Scene> scene;
  std::string source;  // the file, or what the scene was made from, for errors and records
};

struct PyVolume {
  std::shared_ptr<const Volume> volume;
};

// A rendered frame: the session keeps the light-independent image the numpy views look at.
struct PyImage {
  std::shared_ptr<RenderSession> session;
};

// A JSON value (nlohmann's) as the Python object json.loads would give.
py::object jsonToPython(const std::string& json_text);

void bindErrors(py::module_& m);
void bindLibrary(py::module_& m);
void bindVolume(py::module_& m);
void bindScene(py::module_& m);
void bindImage(py::module_& m);
void bindCompare(py::module_& m);

}  // namespace svr::python
