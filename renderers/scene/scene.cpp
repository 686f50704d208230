#include "renderers/scene/scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>
#include <map>

#include "renderers/scene/colour_map.h"
#include "renderers/scene/imported_transfer_function.h"
#include "renderers/scene/scene_palette.h"
#include "renderers/scene/scene_volume.h"
#include "spectral/colour_model.h"
#include "base/data_dir.h"
#include "base/error.h"
#include "base/json_reader.h"
#include "spectral/light_mixer.h"
#include "spectral/spectrum_spec.h"

namespace svr {
namespace fs = std::filesystem;

double Scene::stepWorld() const {
  const glm::dvec3& s = volume.spacing();
  return step_voxels * std::min({s.x, s.y, s.z});
}

namespace {

glm::dvec3 vec3(const JsonReader& r) {
  const auto v = r.numbers(3);
  return {v[0], v[1], v[2]};
}

std::vector<Material> parseMaterials(const JsonReader& list, const SpectrumLibrary& library,
                                     const fs::path& base) {
  std::vector<Material> out;
  for (const std::string& name : list.keys()) {
    const JsonReader m = list.at(name);
    Material mat;
    mat.name = name;
    mat.reflectance = parseSpectrumSpec(m.at("reflectance"), library, base);
    if (auto a = m.find("absorption")) {
      if (!(a->isString() && a->string() == "achromatic"))
        mat.absorption = parseSpectrumSpec(*a, library, base);
    }
    mat.extinction = m.number("opacity", 1.0, 0.0, 1e6);
    mat.specular = m.number("specular", 0.0, 0.0, 1e3);
    mat.xray = m.boolean("xray", false);
    m.rejectUnknownKeys();
    out.push_back(std::move(mat));
  }
  if (out.empty()) list.fail("at least one material is needed");
  return out;
}

int materialIndex(const std::vector<Material>& materials, const JsonReader& name) {
  const std::string n = name.string();
  for (size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == n) return static_cast<int>(i);
  std::string known;
  for (const auto& m : materials) known += (known.empty() ? "" : ", ") + m.name;
  name.fail(fmt::format("no material named '{}' (materials: {})", n, known));
}

TransferFunction parseTransferFunction(const JsonReader& r, std::vector<Material> materials) {
  TransferFunction tf;
  tf.materials = std::move(materials);
  const std::string type = r.string("type", "scalar");
  if (type == "labels") {
    tf.kind = TransferFunction::Kind::kLabels;
    const JsonReader labels = r.at("labels");
    for (const std::string& key : labels.keys()) {
      int label = -1;
      try {
        size_t used = 0;
        label = std::stoi(key, &used);
        if (used != key.size()) label = -1;
      } catch (const std::exception&) {
      }
      if (label < 0 || label > 65535)
        labels.fail(fmt::format("label '{}' is not an integer in 0..65535", key));
      if (static_cast<int>(tf.labels.size()) <= label) tf.labels.resize(label + 1, -1);
      const JsonReader m = labels.at(key);
      tf.labels[label] = materialIndex(tf.materials, m);
    }
  } else if (type == "scalar") {
    const JsonReader points = r.at("points");
    if (!points.isArray() || points.size() == 0) points.fail("needs at least one [value, material]");
    for (size_t i = 0; i < points.size(); ++i) {
      const JsonReader p = points.at(i);
      if (!p.isArray() || p.size() != 2) p.fail("expected [value, \"material\"]");
      tf.points.push_back({p.at(0).number(), materialIndex(tf.materials, p.at(1))});
      if (i > 0 && !(tf.points[i].value > tf.points[i - 1].value))
        p.fail(fmt::format("values must increase: {} follows {}", tf.points[i].value,
                           tf.points[i - 1].value));
    }
    if (auto op = r.find("opacity")) {
      for (size_t i = 0; i < op->size(); ++i) {
        const JsonReader p = op->at(i);
        if (!p.isArray() || p.size() != 2) p.fail("expected [value, factor in 0..1]");
        tf.opacity.emplace_back(p.at(0).number(), p.at(1).number(0.0, 1.0));
        if (i > 0 && !(tf.opacity[i].first > tf.opacity[i - 1].first))
          p.fail(fmt::format("values must increase: {} follows {}", tf.opacity[i].first,
                             tf.opacity[i - 1].first));
      }
    }
  } else {
    r.at("type").fail(fmt::format("unknown transfer function type '{}'; expected scalar or labels",
                                  type));
  }
  r.rejectUnknownKeys();
  return tf;
}

// {"paraview": FILE, "preset": NAME} or {"slicer": FILE}, with "range", "unit_distance",
// "light" and "specular": a colour map from another tool as svr materials.
TransferFunction importedTransferFunction(const JsonReader& r, const fs::path& base,
                                          const SpectrumLibrary& library, const Volume& volume) {
  if (r.contains("paraview") == r.contains("slicer"))
    r.fail("give one of \"paraview\" (a ParaView JSON preset) or \"slicer\" (a Slicer .vp)");
  ColourMap map;
  try {
    map = r.contains("paraview")
              ? readParaViewColourMap((base / r.at("paraview").string()).string(),
                                      r.string("preset", ""))
              : readSlicerVolumeProperty((base / r.at("slicer").string()).string());
  } catch (const Error& e) {
    r.at(r.contains("paraview") ? "paraview" : "slicer").fail(e.what());
  }
  if (auto range = r.find("range")) {
    if (range->isString()) {
      if (range->string() != "data") range->fail("expected [lo, hi] or \"data\"");
      // A distributed render's rank holds one brick when the scene loads; the whole volume's
      // range comes later, and each rank's own would give each a different map.
      if (volume.brick() && !volume.brick()->whole_range)
        range->fail("\"data\" needs the whole volume's value range, which a distributed "
                    "render's rank does not have when the scene loads; give [lo, hi] (svr info "
                    "prints the range)");
      const auto [lo, hi] = volume.valueRange();
      map = map.rescaled(lo, hi);
    } else {
      const auto v = range->numbers(2);
      if (!(v[1] > v[0])) range->fail(fmt::format("[{}, {}] must increase", v[0], v[1]));
      map = map.rescaled(v[0], v[1]);
    }
  }
  ImportOptions options;
  options.unit_distance = r.number("unit_distance", 1.0, 1e-9, 1e9);
  options.light = r.string("light", "D65");
  if (!library.contains(options.light))
    r.at("light").fail(fmt::format("unknown light '{}'", options.light));
  options.specular = r.number("specular", 0.0, 0.0, 1e3);
  r.rejectUnknownKeys();
  const Observer observer = Observer::cie1931(defaultDataDir(), library.grid());
  return importTransferFunction(map, library, observer, options).tf;
}

// The scene's own materials and transfer function, or a colour map imported from another tool.
TransferFunction sceneTransferFunction(const JsonReader& root, const fs::path& base,
                                       const SpectrumLibrary& spectra, const Volume& volume) {
  const JsonReader tf = root.at("transfer_function");
  if (!tf.isObject() || !(tf.contains("paraview") || tf.contains("slicer")))
    return parseTransferFunction(tf, parseMaterials(root.at("materials"), spectra, base));
  if (root.contains("materials"))
    root.at("materials").fail("an imported transfer function makes its own materials; leave "
                              "\"materials\" out");
  return importedTransferFunction(tf, base, spectra, volume);
}

Camera parseCamera(const std::optional<JsonReader>& r, const Volume& volume) {
  // Default framing: the bounding sphere fills the view.
  const double diameter = std::max(glm::length(volume.extent()), 1e-9);
  if (!r) return Camera::orbit(-90.0, 20.0, 2.0 * diameter, 0.0, diameter);
  const double fov = r->number("fov", 0.0, 0.0, 170.0);
  const double zoom = r->number("zoom", 1.0, 1e-3, 1e3);
  Camera c;
  if (r->contains("eye")) {
    c.eye = vec3(r->at("eye"));
    c.target = r->find("target") ? vec3(r->at("target")) : glm::dvec3(0.0);
    c.up = r->find("up") ? vec3(r->at("up")) : glm::dvec3(0, 0, 1);
    c.fov_degrees = fov;
    c.ortho_height = diameter / zoom;
  } else {
    const double distance = r->number("distance", 2.0 * diameter, 1e-9);
    c = Camera::orbit(r->number("azimuth", -90.0, -3600.0, 3600.0),
                      r->number("elevation", 20.0, -90.0, 90.0), distance, fov, diameter / zoom);
    if (fov > 0) {
      // Perspective: zoom narrows the view as it would an orthographic one.
      c.fov_degrees = 2.0 * std::atan(std::tan(0.5 * fov * M_PI / 180.0) / zoom) * 180.0 / M_PI;
    }
  }
  r->rejectUnknownKeys();
  // A camera that cannot make rays (eye on the target, up along the view) fails here, naming
  // the file and the key, rather than at the first render.
  try {
    RayGenerator(c, 1, 1);
  } catch (const Error& e) {
    const std::string what = e.what();
    r->fail(what.rfind("camera: ", 0) == 0 ? what.substr(8) : what);
  }
  return c;
}

}  // namespace

Scene parseScene(const nlohmann::json& json, const std::string& file,
                 const SpectrumLibrary& library, const VolumeLoadOptions& volume_options) {
  const JsonReader root(json, file);
  if (!root.isObject()) root.fail("expected a JSON object");
  const fs::path base = fs::path(file).parent_path();
  Scene scene;
  scene.file = file;
  root.find("description");

  auto volume = loadSceneVolume(root.at("volume"), base, volume_options);
  scene.volume = std::move(volume.volume);
  scene.volume_source = volume.source;

  // A designed palette's spectra join the library as "palette/NAME" for this scene only.
  std::optional<SpectrumLibrary> with_palette;
  if (auto palette = root.find("palette"))
    with_palette = withScenePalette(*palette, base, library);
  const SpectrumLibrary& spectra = with_palette ? *with_palette : library;

  scene.transfer_function = sceneTransferFunction(root, base, spectra, scene.volume);

  const JsonReader lights = root.at("lights");
  if (!lights.isArray() || lights.size() == 0) lights.fail("needs at least one light");
  for (size_t i = 0; i < lights.size(); ++i) {
    const JsonReader l = lights.at(i);
    const std::string name = l.isString() ? l.string() : l.at("name").string();
    for (const auto& other : scene.lights)
      if (other.name == name) l.fail(fmt::format("light name '{}' is used twice", name));
    scene.lights.push_back({name, parseSpectrumSpec(l, spectra, base)});
  }
  if (auto mixes = root.find("light_mixes")) {
    for (const std::string& name : mixes->keys()) {
      const JsonReader mix = mixes->at(name);
      LightMix m{name, {}};
      if (auto handle = mix.find("ngon")) {
        // A handle position in the n-gon mixer (paper §3.3): the scene's lights on a regular
        // polygon in their listed order, weights by normalised inverse squared distance.
        const auto xy = handle->numbers(2);
        const auto weights = LightMixer::regularPolygon(static_cast<int>(scene.lights.size()))
                                 .weights(xy[0], xy[1]);
        for (size_t i = 0; i < weights.size(); ++i)
          if (weights[i] > 0) m.weights.emplace_back(static_cast<int>(i), weights[i]);
        mix.rejectUnknownKeys();
        scene.mixes.push_back(std::move(m));
        continue;
      }
      for (const std::string& light : mix.keys()) {
        int index = -1;
        for (size_t i = 0; i < scene.lights.size(); ++i)
          if (scene.lights[i].name == light) index = static_cast<int>(i);
        if (index < 0) mix.fail(fmt::format("no light named '{}'", light));
        m.weights.emplace_back(index, mix.at(light).number(0.0, 1e6));
      }
      if (m.weights.empty()) mix.fail("a mix needs at least one light");
      scene.mixes.push_back(std::move(m));
    }
  }
  if (auto dir = root.find("light_direction")) {
    const glm::dvec3 d = vec3(*dir);
    if (!(glm::length(d) > 0)) dir->fail("must not be the zero vector");
    scene.light_direction = glm::normalize(d);
  }

  scene.camera = parseCamera(root.find("camera"), scene.volume);
  if (auto image = root.find("image")) {
    scene.width = image->integer("width", 512, 1, 16384);
    scene.height = image->integer("height", 512, 1, 16384);
    image->rejectUnknownKeys();
  }
  if (auto render = root.find("render")) {
    scene.step_voxels = render->number("step", 0.5, 1e-3, 64.0);
    scene.termination = render->number("early_termination", 0.01, 0.0, 1.0);
    scene.bins = render->integer("bins", 1024, 2, 1 << 20);
    if (auto options = render->find("options")) {
      if (!options->isObject()) options->fail("expected {\"backend\": {\"key\": value}}");
      for (const std::string& backend : options->keys())
        if (!options->at(backend).isObject())
          options->at(backend).fail("expected an object of options for this backend");
      scene.renderer_options = options->json();
    }
    render->rejectUnknownKeys();
  }
  if (auto shading = root.find("shading")) {
    scene.shading.ambient = shading->number("ambient", scene.shading.ambient, 0.0, 10.0);
    scene.shading.diffuse = shading->number("diffuse", scene.shading.diffuse, 0.0, 10.0);
    scene.shading.specular = shading->number("specular", scene.shading.specular, 0.0, 10.0);
    scene.shading.shininess = shading->number("shininess", scene.shading.shininess, 1.0, 1e4);
    shading->rejectUnknownKeys();
  }
  if (auto bg = root.find("background")) scene.background = parseSpectrumSpec(*bg, spectra, base);
  if (auto model = root.find("model")) {
    scene.model = model->string();
    if (scene.model != "auto") {
      // Only parseModelName's message lacks the file and key; failing inside the try would
      // name them twice ("scene.json: model: scene.json: model: …").
      const ModelName name = [&] {
        try {
          return parseModelName(scene.model);
        } catch (const Error& e) {
          model->fail(e.what());
        }
      }();
      if (name.kind == ModelKind::kSpectral && name.k > spectra.grid().count)
        model->fail(fmt::format("spectral:{} asks for more bands than the {} samples of the grid",
                                name.k, spectra.grid().count));
      if (name.kind == ModelKind::kLinear)
        model->fail("linear:k has no componentwise product; the renderers take rgb, factor:k, "
                    "spectral:n or auto");
    }
  }
  scene.auto_target = root.number("model_target", 1.0, 1e-3, 100.0);
  if (auto tol = root.find("tolerances")) scene.tolerances = tol->json();
  root.rejectUnknownKeys();
  return scene;
}

Scene loadScene(const std::string& path, const SpectrumLibrary& library,
                const VolumeLoadOptions& volume_options) {
  return parseScene(JsonReader::parseFile(path), path, library, volume_options);
}

}  // namespace svr
