// svr.Image: a rendered light-independent image. S and T are read-only numpy views of its planes
// (H × W × k and H × W × t, no copy); relight applies any light afterwards (post-illumination,
// design.md §5) and returns sRGB; save writes what `svr render` writes.

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>

#include "harness/image_files.h"
#include "python/bindings.h"
#include "base/error.h"
#include "spectral/image_difference.h"

namespace svr::python {
namespace {

// Planes [first, first + count) as an H × W × count float32 view that keeps the session alive.
py::array planesView(const PyImage& im, int first, int count) {
  const LightIndependentImage& image = im.session->image();
  const auto pixels = static_cast<py::ssize_t>(image.pixels());
  const float* data = image.planeFloat(first).data();
  auto* keep = new std::shared_ptr<RenderSession>(im.session);
  py::capsule owner(keep, [](void* p) { delete static_cast<std::shared_ptr<RenderSession>*>(p); });
  const py::ssize_t f = sizeof(float);
  py::array view(py::dtype::of<float>(), {py::ssize_t(image.height()), py::ssize_t(image.width()),
                                          py::ssize_t(count)},
                 {image.width() * f, f, pixels * f}, data, owner);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

// A light as the user names it: a library or scene name, {name: weight}, or 81 values.
Spectrum lightOf(const RenderSession& s, const py::object& light) {
  if (py::isinstance<py::str>(light)) return s.light(light.cast<std::string>());
  if (py::isinstance<py::dict>(light)) {
    std::vector<std::pair<std::string, double>> weights;
    for (const auto& [name, w] : light.cast<py::dict>())
      weights.emplace_back(py::str(name).cast<std::string>(), w.cast<double>());
    return s.mix(weights);
  }
  const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(light);
  const WavelengthGrid& grid = s.spectra().grid;
  if (!values || values.ndim() != 1 || values.size() != grid.count)
    throw py::value_error(fmt::format(
        "relight: a light is a name, {{name: weight}} or {} values on {}", grid.count,
        grid.describe()));
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(values.data(), grid.count);
  try {
    return s.ownLight(Spectrum(grid, v), "relight");  // checks the values
  } catch (const Error& e) {
    throw py::value_error(e.what());  // a bad argument, not a bad file
  }
}

py::array relight(const PyImage& im, const py::object& light, bool linear, py::object out) {
  const RenderSession& s = *im.session;
  const LightIndependentImage& image = s.image();
  const Spectrum l = lightOf(s, light);
  const std::vector<py::ssize_t> shape{image.height(), image.width(), 3};
  const auto want = linear ? py::dtype::of<float>() : py::dtype::of<std::uint8_t>();
  py::array result = out.is_none() ? py::array(want, shape) : out.cast<py::array>();
  if (!result.dtype().is(want) || result.ndim() != 3 || result.shape(0) != shape[0] ||
      result.shape(1) != shape[1] || result.shape(2) != 3 ||
      !(result.flags() & py::array::c_style) || !result.writeable())
    throw py::value_error(fmt::format("relight: out must be a writeable C-contiguous {} array "
                                      "of shape ({}, {}, 3)",
                                      linear ? "float32" : "uint8", shape[0], shape[1]));
  const std::size_t n = 3 * image.pixels();
  void* data = result.mutable_data();
  {
    py::gil_scoped_release released;
    if (linear) s.relightLinear(l, {static_cast<float*>(data), n});
    else s.relightSrgb8(l, {static_cast<std::uint8_t*>(data), n});
  }
  return result;
}

// ΔE2000 per pixel against another render of the same view (the spectral:81 reference, say),
// both relit under one light, as the harness measures it (spectral/image_difference.h).
py::tuple deltaE2000(const PyImage& im, const PyImage& reference, const py::object& light) {
  const RenderSession& s = *im.session;
  const RenderSession& r = *reference.session;
  const Spectrum l = lightOf(s, light);
  ImageDifference d;
  {
    py::gil_scoped_release released;
    d = compareRelit(s.image(), *s.model().model, r.image(), *r.model().model, l,
                     s.spectra().observer.xyz(l), 0.98, s.scene().background);
  }
  py::array_t<float> map({py::ssize_t(s.image().height()), py::ssize_t(s.image().width())});
  std::copy(d.map.begin(), d.map.end(), map.mutable_data());
  py::dict stats;
  stats["mean"] = d.stats.mean;
  stats["p95"] = d.stats.p95;
  stats["max"] = d.stats.max;
  stats["covered"] = d.covered;
  return py::make_tuple(map, stats);
}

py::bytes reprPng(const PyImage& im) {
  const RenderSession& s = *im.session;
  const LightIndependentImage& image = s.image();
  const std::string name = s.lightNames().empty() ? "D65" : s.lightNames().front();
  std::vector<std::uint8_t> rgb(3 * image.pixels());
  s.relightSrgb8(s.light(name), rgb);
  const std::vector<std::uint8_t> png = encodeSrgbPng(rgb, image.width(), image.height());
  return py::bytes(reinterpret_cast<const char*>(png.data()), png.size());
}

}  // namespace

void bindImage(py::module_& m) {
  py::class_<PyImage>(m, "Image", "A light-independent image: relight it under any light.")
      .def_property_readonly(
          "S", [](const PyImage& im) { return planesView(im, 0, im.session->image().channels()); },
          "The scattered light, H × W × k float32 (a read-only view, no copy).")
      .def_property_readonly(
          "T",
          [](const PyImage& im) {
            const LightIndependentImage& image = im.session->image();
            return planesView(im, image.channels(), image.transmittanceChannels());
          },
          "The transmittance to the backdrop, H × W × t float32, t = 1 or k (a read-only view).")
      .def_property_readonly(
          "model",
          [](const PyImage& im) {
            nlohmann::json record = im.session->model().record();
            record["light_matrix"] = toString(im.session->model().model->lightMatrixKind());
            return jsonToPython(record.dump());
          },
          "The colour model: asked, model, k, description (and auto's figures).")
      .def_property_readonly("renderer", [](const PyImage& im) { return im.session->renderer().name(); })
      .def_property_readonly("width", [](const PyImage& im) { return im.session->image().width(); })
      .def_property_readonly("height", [](const PyImage& im) { return im.session->image().height(); })
      .def_property_readonly("lights", [](const PyImage& im) { return im.session->lightNames(); },
                             "The scene's lights, then its mixes, by name.")
      .def_property_readonly(
          "timings",
          [](const PyImage& im) {
            const RenderSession::Timings& t = im.session->timings();
            py::dict d;
            d["setup_ms"] = t.setup;
            d["model_ms"] = t.model;
            d["classify_ms"] = t.classify;
            d["render_ms"] = t.render;
            return d;
          },
          "Milliseconds the library spent: setting up (the model and the classification "
          "included), making the model, classifying, rendering.")
      .def("relight", &relight, py::arg("light"), py::arg("linear") = false,
           py::arg("out") = py::none(),
           "The image under a light: a library or scene name ('D65'), a mix {'D65': 0.5, "
           "'A': 0.5}, or 81 values on the grid; each at unit luminance, the scene's backdrop "
           "showing through. H × W × 3 uint8 sRGB, or float32 linear sRGB with linear=True; "
           "`out` reuses an array of that shape.")
      .def(
          "save",
          [](const PyImage& im, const std::string& dir) {
            py::gil_scoped_release released;
            im.session->save(dir);
          },
          py::arg("dir"),
          "Writes what `svr render --out DIR` writes: light_independent.exr and its model, one "
          "PNG per scene light and mix, render.json.")
      .def("delta_e2000", &deltaE2000, py::arg("reference"), py::arg("light"),
           "ΔE2000 against another render of the same view (e.g. model='spectral:81'), both "
           "relit under `light`: an H × W float32 map (0 where neither image covers the pixel) "
           "and {'mean', 'p95', 'max', 'covered'} over the covered pixels, as svr compare "
           "measures.")
      .def("_repr_png_", &reprPng)
      .def("__repr__", [](const PyImage& im) {
        const LightIndependentImage& image = im.session->image();
        return fmt::format("<svr.Image {}×{} {} {}>", image.width(), image.height(),
                           im.session->renderer().name(), im.session->model().model->name());
      });
}

}  // namespace svr::python
