// svr: the spectral volume renderer's command line.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>
#include <fmt/ranges.h>

#include "harness/info_command.h"
#include "harness/model_error_command.h"
#include "harness/relight_command.h"
#include "harness/render_command.h"
#include "renderers/core/memory_budget.h"
#include "renderers/registry.h"
#include "spectral/data_dir.h"
#include "spectral/error.h"

int main(int argc, char** argv) {
  CLI::App app{"svr — spectral volume rendering with post-illumination (Bergner et al. 2002)"};
  app.require_subcommand(1);
  std::string data_dir = svr::defaultDataDir();
  app.add_option("--data", data_dir, "data directory (spectra/, volumes/, scenes/)")
      ->capture_default_str();

  svr::ModelErrorOptions me;
  auto* model_error = app.add_subcommand(
      "model-error", "accuracy of every colour model against the exact spectral product");
  model_error->add_option("--lights", me.lights, "library light names (default A D65 F2 F7 F11 LED-B1)")
      ->delimiter(',');
  model_error->add_option("--reflectances", me.reflectances,
                          "reflectance names, or 'munsell' / 'colorchecker', as the test set")
      ->delimiter(',');
  model_error->add_option("--palette", me.palette,
                          "palette or scene JSON: train and test on its own lights × materials")
      ->check(CLI::ExistingFile);
  model_error->add_option("--json", me.json_path, "write every row as JSON to this file");
  model_error->add_option("--kmin", me.k_min, "smallest k")->capture_default_str();
  model_error->add_option("--kmax", me.k_max, "largest k")->capture_default_str();
  model_error->add_flag("--contrast", me.contrast,
                        "also show closed-form (unrefined) sharpening, which is unstable");
  model_error->add_flag("-q,--quiet", me.quiet, "no progress bar");
  model_error->callback([&] {
    me.data_dir = data_dir;
    svr::runModelError(me);
  });

  // ---- svr info FILE [--raw-…] [--memory-budget] ---------------------------------------------
  svr::InfoOptions info;
  std::vector<int> raw_dims;
  std::vector<double> raw_spacing;
  std::string raw_type, raw_endian = "little", memory_budget;
  std::uint64_t raw_header_bytes = 0;
  auto* info_command = app.add_subcommand(
      "info", "what a volume file holds: layout, spacing, world box, value range, histogram");
  info_command->add_option("FILE", info.path, "volume file: .nrrd, .nhdr, .mhd, .mha, or raw")
      ->required();
  auto* raw_dims_option =
      info_command->add_option("--raw-dims", raw_dims, "headerless raw file: voxels X,Y,Z")
          ->delimiter(',');
  auto* raw_type_option =
      info_command->add_option("--raw-type", raw_type,
                               "headerless raw file: uint8, int8, uint16, int16, uint32, int32, "
                               "float32 or float64");
  auto* raw_endian_option =
      info_command->add_option("--raw-endian", raw_endian, "headerless raw file: byte order")
          ->check(CLI::IsMember({"little", "big"}))
          ->capture_default_str();
  auto* raw_spacing_option =
      info_command->add_option("--raw-spacing", raw_spacing, "headerless raw file: X,Y,Z")
          ->delimiter(',');
  auto* raw_header_option = info_command->add_option("--raw-header-bytes", raw_header_bytes,
                                                     "headerless raw file: bytes to skip first");
  info_command->add_option("--memory-budget", memory_budget,
                           "most bytes of voxels to load, e.g. 512M or 2G (default: the "
                           "memory available now)");
  info_command->callback([&] {
    if (!memory_budget.empty())
      info.memory_budget = svr::parseByteSize(memory_budget, "--memory-budget");
    const bool raw = raw_dims_option->count() + raw_type_option->count() +
                         raw_endian_option->count() + raw_spacing_option->count() +
                         raw_header_option->count() >
                     0;
    if (raw) {
      if (raw_dims.size() != 3 || raw_type.empty())
        throw svr::Error(
            fmt::format("{}: a raw layout needs --raw-dims X,Y,Z and --raw-type", info.path));
      svr::RawLayout layout;
      layout.dims = {raw_dims[0], raw_dims[1], raw_dims[2]};
      try {
        layout.type = svr::parseScalarType(raw_type);
      } catch (const svr::Error& e) {
        throw svr::Error(fmt::format("--raw-type: {}", e.what()));
      }
      layout.endian = raw_endian == "big" ? svr::Endian::kBig : svr::Endian::kLittle;
      if (raw_spacing_option->count() > 0) {
        if (raw_spacing.size() != 3)
          throw svr::Error(
              fmt::format("--raw-spacing: {} values given; expected X,Y,Z", raw_spacing.size()));
        layout.spacing = {raw_spacing[0], raw_spacing[1], raw_spacing[2]};
      }
      layout.header_bytes = raw_header_bytes;
      info.raw = layout;
    }
    svr::runInfo(info);
  });
  // ---- end of svr info ------------------------------------------------------------------------

  svr::RenderOptions render;
  std::string render_budget;
  auto* render_command = app.add_subcommand(
      "render", "render a scene once, relight it under every scene light and mix");
  render_command->add_option("SCENE", render.scene, "scene JSON (see docs/scenes.md)")->required();
  render_command->add_option("--renderer", render.renderer,
                             fmt::format("backend: {}", fmt::join(svr::rendererNames(), ", ")))
      ->capture_default_str();
  render_command->add_option("--model", render.model,
                             "colour model: rgb, factor:k, spectral:n or auto (default: the scene's)");
  render_command->add_option("--out", render.out_dir, "output folder")->required();
  render_command->add_option("--width", render.width, "image width (default: the scene's)");
  render_command->add_option("--height", render.height, "image height (default: the scene's)");
  render_command->add_flag("--half", render.half, "store the light-independent EXR as half floats");
  render_command->add_option("--option", render.options,
                             "backend option BACKEND.KEY=VALUE (repeatable), e.g. splat.mode=sheet");
  render_command->add_option("--memory-budget", render_budget, "most bytes of voxels to load");
  render_command->add_flag("-q,--quiet", render.quiet, "no progress bar or summary");
  render_command->callback([&] {
    render.data_dir = data_dir;
    if (!render_budget.empty())
      render.memory_budget = svr::parseByteSize(render_budget, "--memory-budget");
    if ((render.width && *render.width < 1) || (render.height && *render.height < 1))
      throw svr::Error("render: --width and --height must be ≥ 1");
    svr::runRender(render);
  });

  svr::RelightOptions relight;
  auto* relight_command = app.add_subcommand(
      "relight", "apply a light or light mix to a saved light-independent image");
  relight_command->add_option("IMAGE", relight.image, "light_independent.exr from svr render")
      ->required();
  relight_command->add_option("--light", relight.light, "library light name, e.g. D65");
  relight_command->add_option("--mix", relight.mix, "weighted lights, e.g. A:0.3,F11:0.7");
  relight_command->add_option("--model", relight.model,
                              "colour model JSON (default: the one named in the EXR)");
  relight_command->add_option("--background", relight.background,
                              "library reflectance seen through the volume");
  relight_command->add_option("--exposure", relight.exposure, "scale of the relit image")
      ->capture_default_str();
  relight_command->add_option("--out", relight.out, "PNG to write")->required();
  relight_command->callback([&] {
    relight.data_dir = data_dir;
    svr::runRelight(relight);
  });

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const svr::Error& e) {
    fmt::print(stderr, "svr: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "svr: internal error: {}\n", e.what());
    return 3;
  }
  return 0;
}
