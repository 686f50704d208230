// svr.compare: `svr compare` on a scene object — the reference and every backend × model, each
// relit under every light and measured — returning report.json as a dict.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <random>

#include "harness/compare_command.h"
#include "python/bindings.h"

namespace svr::python {
namespace {

// A fresh folder under the system's temporary one, removed when the comparison is done.
struct ScratchFolder {
  std::filesystem::path path;
  ScratchFolder() {
    std::random_device entropy;
    for (int attempt = 0; attempt < 16; ++attempt) {
      path = std::filesystem::temp_directory_path() / fmt::format("svr-compare-{:08x}", entropy());
      if (std::filesystem::create_directory(path)) return;
    }
    throw Error(fmt::format("compare: cannot make a folder under {}",
                            std::filesystem::temp_directory_path().string()));
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

py::object compare(const PyScene& s, std::vector<std::string> renderers,
                   std::vector<std::string> models, int width, int height,
                   const std::string& out, bool charts) {
  std::optional<ScratchFolder> scratch;
  if (out.empty()) scratch.emplace();
  CompareOptions o;
  o.data_dir = s.spectra->data_dir;
  o.scene = s.source;
  o.renderers = std::move(renderers);
  o.models = std::move(models);
  o.width = width;
  o.height = height;
  o.out_dir = out.empty() ? scratch->path.string() : out;
  o.charts = charts;
  o.quiet = true;
  std::string report;
  {
    py::gil_scoped_release released;
    report = runComparison(*s.scene, o).report.dump();
  }
  return jsonToPython(report);
}

}  // namespace

void bindCompare(py::module_& m) {
  m.def("compare", &compare, py::arg("scene"), py::arg("renderers") = std::vector<std::string>{},
        py::arg("models") = std::vector<std::string>{}, py::arg("width") = 0,
        py::arg("height") = 0, py::arg("out") = "", py::arg("charts") = false,
        "`svr compare` on a scene: the reference (raycast, spectral:81) and every renderer × "
        "model (empty lists: every built backend; rgb, factor:3, 4, 6, 8, spectral:31), relit "
        "and measured under every light. Returns report.json as a dict; `out` keeps the "
        "folder (images, ΔE2000 maps, and with charts=True the charts and report.html).");
}

}  // namespace svr::python
