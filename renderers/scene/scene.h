#pragma once
// A scene file (JSON, documented in docs/scenes.md): the volume and its transfer function,
// materials and lights as spectra, light mixes, light direction, camera, image size, sampling,
// shading, background, colour model and tolerances. Loading checks every key: an unknown key, a
// wrong type or an out-of-range value is an svr::Error naming the file, the key path and the
// value.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "renderers/scene/camera.h"
#include "renderers/scene/transfer_function.h"
#include "renderers/volume/volume.h"
#include "renderers/volume/volume_io.h"
#include "spectral/spectrum_library.h"

namespace svr {

struct Shading {
  double ambient = 0.25, diffuse = 0.75, specular = 0.5, shininess = 24.0;
};

struct SceneLight {
  std::string name;
  Spectrum spectrum;  // as given; relighting normalises it to unit luminance
};

struct LightMix {
  std::string name;
  std::vector<std::pair<int, double>> weights;  // (index into lights, weight)
};

struct Scene {
  std::string file;
  Volume volume;
  std::string volume_source;  // path or procedural description
  TransferFunction transfer_function;
  std::vector<SceneLight> lights;
  std::vector<LightMix> mixes;
  std::optional<glm::dvec3> light_direction;  // towards the light, world; empty = headlight
  Camera camera;
  int width = 512, height = 512;
  double step_voxels = 0.5;         // sample spacing in units of the smallest voxel spacing
  double termination = 0.01;        // early ray termination when max T < this; 0 = off
  int bins = 1024;
  nlohmann::json renderer_options = nlohmann::json::object();  // render.options, per backend
  Shading shading;
  std::optional<Spectrum> background;  // reflectance of a backdrop; empty = black
  std::string model = "factor:6";      // rgb, factor:k, spectral:n, or auto
  double auto_target = 1.0;            // auto: mean ΔE2000 the palette must stay within
  nlohmann::json tolerances;           // for the harness, passed through

  double stepWorld() const;
};

Scene loadScene(const std::string& path, const SpectrumLibrary& library,
                const VolumeLoadOptions& volume_options = {});
// The same from JSON already in memory; `file` names it and anchors relative paths.
Scene parseScene(const nlohmann::json& json, const std::string& file,
                 const SpectrumLibrary& library, const VolumeLoadOptions& volume_options = {});

}  // namespace svr
