// svr.library (the spectra of the data folder: lights, ColorChecker, Munsell, absorbers) and
// svr.backends() (the registry's backends with their capabilities and options).

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "renderers/registry.h"
#include "base/error.h"

namespace svr::python {
namespace {

SpectrumKind kindNamed(const std::string& kind) {
  if (kind == "light") return SpectrumKind::kLight;
  if (kind == "reflectance") return SpectrumKind::kReflectance;
  if (kind == "absorbance") return SpectrumKind::kAbsorbance;
  throw py::value_error(fmt::format(
      "library.names: kind '{}' is not one of 'light', 'reflectance', 'absorbance'", kind));
}

py::array_t<double> toNumpy(const Eigen::VectorXd& v) {
  py::array_t<double> out(v.size());
  std::copy(v.data(), v.data() + v.size(), out.mutable_data());
  return out;
}

py::dict backendDict(const BackendEntry& e) {
  py::dict d;
  d["name"] = e.info.name;
  d["summary"] = e.info.summary;
  d["built"] = static_cast<bool>(e.make);
  if (!e.make) d["unavailable"] = e.unavailable;
  const BackendCapabilities& c = e.info.supports;
  py::dict caps;
  caps["perspective"] = c.perspective;
  caps["spectral_transmittance"] = c.spectral_transmittance;
  caps["max_channels"] = c.max_channels;
  caps["needs_gl"] = c.needs_gl;
  caps["bricks"] = c.bricks;
  caps["reference"] = c.reference;
  d["supports"] = caps;
  py::list options;
  for (const OptionSpec& o : e.info.options) {
    py::dict od;
    od["key"] = o.key;
    od["help"] = o.help;
    if (o.kind == OptionSpec::Kind::kChoice) {
      od["kind"] = "choice";
      od["choices"] = o.choices;
      od["default"] = o.choices.front();
    } else {
      od["kind"] = o.kind == OptionSpec::Kind::kInteger ? "integer" : "number";
      od["range"] = py::make_tuple(o.lo, o.hi);
      od["default"] = o.fallback;
    }
    options.append(od);
  }
  d["options"] = options;
  return d;
}

}  // namespace

void bindLibrary(py::module_& m) {
  py::module_ lib = m.def_submodule("library", "The spectra of svr's data folder.");
  lib.def(
      "spectrum",
      [](const std::string& name, const std::string& data_dir) {
        return toNumpy(spectraFor(data_dir)->library.get(name).values());
      },
      py::arg("name"), py::arg("data_dir") = "",
      "The spectrum of a library name ('D65', 'F11', 'LED-B3', 'Munsell/5R 5/10', 'Hb', …) on "
      "the standard grid (library.wavelengths()), as stored (lights not normalised).");
  lib.def(
      "names",
      [](std::optional<std::string> kind, const std::string& data_dir) {
        const SpectrumLibrary& l = spectraFor(data_dir)->library;
        return kind ? l.names(kindNamed(*kind)) : l.names();
      },
      py::arg("kind") = py::none(), py::arg("data_dir") = "",
      "Every name in the library, or those of one kind: 'light', 'reflectance' or "
      "'absorbance'; sorted.");
  lib.def(
      "wavelengths",
      [](const std::string& data_dir) {
        const WavelengthGrid& g = spectraFor(data_dir)->grid;
        Eigen::VectorXd nm(g.count);
        for (int i = 0; i < g.count; ++i) nm[i] = g.wavelength(i);
        return toNumpy(nm);
      },
      py::arg("data_dir") = "", "The grid's wavelengths in nm (380, 385, …, 780).");

  m.def(
      "backends",
      [] {
        py::list out;
        for (const BackendEntry& e : backendEntries()) out.append(backendDict(e));
        return out;
      },
      "Every backend in the registry: name, summary, whether built, capabilities and options "
      "(key, kind, range or choices, default, help), as `svr render --help-options` lists them.");
}

}  // namespace svr::python
