// svr.Scene: a scene file (or the same as a dict), checked as strictly as `svr render` checks
// it; with_volume swaps in a numpy volume; render makes an Image (image_binding.cpp) through
// the library's RenderSession, without the GIL.

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <filesystem>

#include "python/bindings.h"
#include "python/render_call.h"
#include "renderers/render/scene_render.h"
#include "base/json_reader.h"

namespace svr::python {
namespace {

// {"splat.mode": "sheet"} or {"splat": {"mode": "sheet"}} → "splat.mode=sheet", as --option.
std::vector<std::string> optionAssignments(const py::object& options) {
  std::vector<std::string> out;
  if (options.is_none()) return out;
  if (!py::isinstance<py::dict>(options))
    throw py::type_error("render: options must be a dict such as {'splat.mode': 'sheet'}");
  for (const auto& [key, value] : options.cast<py::dict>()) {
    const std::string k = py::str(key);
    if (py::isinstance<py::dict>(value)) {
      for (const auto& [inner, v] : value.cast<py::dict>())
        out.push_back(fmt::format("{}.{}={}", k, py::str(inner).cast<std::string>(),
                                  py::str(v).cast<std::string>()));
    } else {
      out.push_back(fmt::format("{}={}", k, py::str(value).cast<std::string>()));
    }
  }
  return out;
}

PyScene loadFile(const std::string& path, const std::string& data_dir) {
  PyScene s{spectraFor(data_dir), nullptr, path};
  s.scene = std::make_shared<const Scene>(loadScene(path, s.spectra->library));
  return s;
}

PyScene fromDict(const py::dict& d, const std::string& base_dir, const std::string& data_dir) {
  const std::string text = py::module_::import("json").attr("dumps")(d).cast<std::string>();
  // parseScene anchors relative paths at the named file's folder.
  const std::string source = (std::filesystem::path(base_dir) / "<dict>").string();
  PyScene s{spectraFor(data_dir), nullptr, source};
  s.scene = std::make_shared<const Scene>(
      parseScene(JsonReader::parse(text, source), source, s.spectra->library));
  return s;
}

py::object render(const PyScene& s, const std::string& renderer, const std::string& model,
                  int width, int height, const py::object& options, const py::object& progress) {
  RenderSettings settings;
  settings.renderer = renderer;
  settings.model = model;
  settings.width = width;
  settings.height = height;
  settings.options = optionAssignments(options);
  std::shared_ptr<RenderSession> session;
  ReleasedCall call(progress);
  call.run([&](const ProgressFn& report, const std::atomic<bool>* stop) {
    session = std::make_shared<RenderSession>(s.spectra, *s.scene, settings, s.source);
    session->render(report, stop);
  });
  return py::cast(PyImage{std::move(session)});
}

}  // namespace

void bindScene(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A scene: volume, transfer function, lights, camera, image.")
      .def_static("load", &loadFile, py::arg("path"), py::arg("data_dir") = "",
                  "Loads a scene file (docs/scenes.md) and its volume; raises svr.Error naming "
                  "the file, key and value of anything wrong.")
      .def_static("from_dict", &fromDict, py::arg("scene"), py::arg("base_dir") = ".",
                  py::arg("data_dir") = "",
                  "A scene from a dict with a scene file's keys; relative paths in it are taken "
                  "from base_dir. The same checks and messages as a file.")
      .def(
          "with_volume",
          [](const PyScene& s, const PyVolume& v) {
            auto scene = std::make_shared<Scene>(*s.scene);
            scene->volume = *v.volume;  // the voxels are shared, not copied
            scene->volume_source = v.volume->source();
            return PyScene{s.spectra, std::move(scene), s.source};
          },
          py::arg("volume"),
          "This scene with another volume (svr.Volume.from_numpy); its transfer function, "
          "lights and camera stay.")
      .def("render", &render, py::arg("renderer") = "raycast", py::arg("model") = "",
           py::arg("width") = 0, py::arg("height") = 0, py::arg("options") = py::none(),
           py::arg("progress") = py::none(),
           "Renders the light-independent image with a backend ('raycast', 'shearwarp', "
           "'splat', 'gl') and a colour model ('rgb', 'factor:k', 'spectral:n', 'auto'; '' = the "
           "scene's). width/height 0 keep the scene's; options as {'splat.mode': 'sheet'}; "
           "progress(fraction) is called as it goes. The GIL is released; Ctrl-C stops it.")
      .def_property_readonly("file", [](const PyScene& s) { return s.source; })
      .def_property_readonly("model", [](const PyScene& s) { return s.scene->model; })
      .def_property_readonly("width", [](const PyScene& s) { return s.scene->width; })
      .def_property_readonly("height", [](const PyScene& s) { return s.scene->height; })
      .def_property_readonly("volume",
                             [](const PyScene& s) {
                               return PyVolume{std::make_shared<const Volume>(s.scene->volume)};
                             })
      .def_property_readonly(
          "lights", [](const PyScene& s) { return sceneIlluminationNames(*s.scene); },
          "The scene's lights, then its mixes, by name.")
      .def("__repr__", [](const PyScene& s) {
        return fmt::format("<svr.Scene {} {}×{} {}>", s.source, s.scene->width, s.scene->height,
                           s.scene->volume_source);
      });
}

}  // namespace svr::python
