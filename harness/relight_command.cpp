#include "harness/relight_command.h"

#include <CLI/CLI.hpp>
#include <memory>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "harness/command.h"
#include "harness/image_files.h"
#include "renderers/registry.h"
#include "spectral/colorimetry.h"
#include "base/error.h"
#include "spectral/light_mixer.h"
#include "spectral/post_illumination.h"
#include "spectral/spectrum_library.h"

namespace svr {
namespace fs = std::filesystem;

int runRelight(const RelightOptions& o) {
  if (o.light.empty() == o.mix.empty())
    throw Error("relight: give exactly one of --light NAME or --mix NAME:W,NAME:W");
  if (!std::isfinite(o.exposure) || o.exposure <= 0)
    throw Error(fmt::format("relight: --exposure {} must be > 0", o.exposure));
  // A backend without a relighter (or not built) fails before any file is read.
  const std::unique_ptr<Relighter> device =
      o.relighter.empty() ? nullptr : makeRelighter(o.relighter);
  std::map<std::string, std::string> attributes;
  const LightIndependentImage image = readLightIndependentExr(o.image, &attributes);
  std::string model_path = o.model;
  if (model_path.empty()) {
    if (!attributes.count("model_file"))
      throw Error(fmt::format("{}: names no model file; pass --model", o.image));
    model_path = (fs::path(o.image).parent_path() / attributes["model_file"]).string();
  }
  const auto model = loadModel(model_path);
  const WavelengthGrid grid = model->grid();
  const auto library = SpectrumLibrary::load(o.data_dir, grid);
  const auto observer = Observer::cie1931(o.data_dir, grid);
  auto unitLight = [&](const std::string& name) {
    return observer.unitLuminance(library.get(name)).values();
  };
  Eigen::VectorXd light;
  if (!o.light.empty()) {
    light = unitLight(o.light);
  } else {
    std::vector<Eigen::VectorXd> lights;
    std::vector<double> weights;
    std::stringstream ss(o.mix);
    std::string item;
    while (std::getline(ss, item, ',')) {
      const auto colon = item.rfind(':');
      if (colon == std::string::npos)
        throw Error(fmt::format("relight: --mix item '{}' is not NAME:WEIGHT", item));
      double w = 0.0;
      try {
        size_t used = 0;
        w = std::stod(item.substr(colon + 1), &used);
        if (used != item.size() - colon - 1) throw std::invalid_argument("");
      } catch (const std::exception&) {
        throw Error(fmt::format("relight: --mix weight '{}' of '{}' is not a number",
                                item.substr(colon + 1), item.substr(0, colon)));
      }
      if (!std::isfinite(w) || w < 0)
        throw Error(fmt::format("relight: --mix weight {} of '{}' must be ≥ 0", w,
                                item.substr(0, colon)));
      lights.push_back(unitLight(item.substr(0, colon)));
      weights.push_back(w);
    }
    light = mixLights(lights, weights);
  }
  PostIlluminator post(*model);
  post.setLight(Spectrum(grid, light), o.exposure);
  if (!o.background.empty()) post.setBackground(model->project(library.get(o.background)));
  std::vector<std::uint8_t> rgb(3 * image.pixels());
  if (device) {
    device->setImage(image);
    device->relightSrgb8(post.foldedMatrix(image, RelitSpace::kLinearSrgb), rgb);
  } else {
    post.relightSrgb8(image, rgb);
  }
  writeSrgbPng(rgb, image.width(), image.height(), o.out);
  return 0;
}

namespace commands {

CommandEntry relight() {
  return {"relight", "apply a light or light mix to a saved light-independent image",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<RelightOptions>();
            sub.add_option("IMAGE", o->image, "light_independent.exr from svr render")->required();
            sub.add_option("--light", o->light, "library light name, e.g. D65");
            sub.add_option("--mix", o->mix, "weighted lights, e.g. A:0.3,F11:0.7");
            sub.add_option("--model", o->model,
                           "colour model JSON (default: the one named in the EXR)");
            sub.add_option("--background", o->background,
                           "library reflectance seen through the volume");
            sub.add_option("--exposure", o->exposure, "scale of the relit image")
                ->capture_default_str();
            sub.add_option("--out", o->out, "PNG to write")->required();
            sub.add_option("--on", o->relighter,
                           "relight on this backend's device instead of the CPU (gl: an OpenGL "
                           "fragment shader)");
            runOnParse(sub, context, o, &runRelight);
          }};
}

}  // namespace commands

}  // namespace svr
