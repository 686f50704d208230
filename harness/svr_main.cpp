// svr: the spectral volume renderer's command line.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>
#include <fmt/ranges.h>

#include "harness/design_command.h"
#include "harness/info_command.h"
#include "harness/interrupt.h"
#include "harness/compare_command.h"
#include "harness/demo_command.h"
#include "harness/model_error_command.h"
#include "harness/sweep_command.h"
#include "harness/relight_command.h"
#include "harness/render_command.h"
#include "renderers/core/memory_budget.h"
#include "renderers/registry.h"
#include "spectral/data_dir.h"
#include "spectral/error.h"

namespace {

// An image size given on the command line: the scene file's image.width/height range, checked
// before any loading or rendering.
void checkImageSize(const std::string& command, const std::string& flag, int value) {
  if (value < 1 || value > 16384)
    throw svr::Error(fmt::format("{}: {} {} is outside 1..16384", command, flag, value));
}

}  // namespace

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
  std::string splat_mode;
  render_command->add_option("--splat-mode", splat_mode, "splat compositing: sheet or direct")
      ->check(CLI::IsMember({"sheet", "direct"}));
  render_command->add_option("--memory-budget", render_budget, "most bytes of voxels to load");
  render_command->add_flag("-q,--quiet", render.quiet, "no progress bar or summary");
  render_command->callback([&] {
    render.data_dir = data_dir;
    if (!splat_mode.empty()) render.options.push_back("splat.mode=" + splat_mode);
    if (!render_budget.empty())
      render.memory_budget = svr::parseByteSize(render_budget, "--memory-budget");
    if (render.width) checkImageSize("render", "--width", *render.width);
    if (render.height) checkImageSize("render", "--height", *render.height);
    svr::installInterruptHandler();
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
  relight_command->add_flag("--gl", relight.gl,
                            "relight in an OpenGL fragment shader (OSMesa) instead of on the CPU");
  relight_command->callback([&] {
    relight.data_dir = data_dir;
    svr::runRelight(relight);
  });

  // ---- svr compare / sweep / demo (the harness) -----------------------------------------------
  svr::CompareOptions compare;
  int compare_status = 0;
  auto* compare_command = app.add_subcommand(
      "compare", "reference and every backend × model on one scene: ΔE2000, times, report");
  compare_command->add_option("SCENE", compare.scene, "scene JSON")->required();
  compare_command->add_option("--renderers", compare.renderers, "backends (default: all)")
      ->delimiter(',');
  compare_command->add_option("--models", compare.models,
                              "models (default rgb,factor:3,factor:4,factor:6,factor:8,spectral:31)")
      ->delimiter(',');
  compare_command->add_option("--variant", compare.variants,
                              "extra run with a backend option, BACKEND.KEY=VALUE (repeatable)");
  compare_command->add_option("--out", compare.out_dir, "report folder")->required();
  auto* compare_width =
      compare_command->add_option("--width", compare.width, "image width (default: the scene's)");
  auto* compare_height =
      compare_command->add_option("--height", compare.height, "image height (default: the scene's)");
  compare_command->add_flag("-q,--quiet", compare.quiet, "no progress bar or table");
  compare_command->callback([&] {
    compare.data_dir = data_dir;
    if (compare_width->count()) checkImageSize("compare", "--width", compare.width);
    if (compare_height->count()) checkImageSize("compare", "--height", compare.height);
    compare_status = svr::runCompare(compare);
  });

  svr::SweepOptions sweep;
  auto* sweep_command = app.add_subcommand(
      "sweep", "ΔE2000 and time against one parameter, with jumps and blow-ups flagged");
  sweep_command->add_option("SCENE", sweep.scene, "scene JSON")->required();
  sweep_command->add_option("--param", sweep.param,
                            "NAME=FROM:TO:STEP; NAME: azimuth, elevation, zoom, step, k, depth "
                            "or BACKEND.KEY")
      ->required();
  sweep_command->add_option("--renderers", sweep.renderers, "backends (default: all)")
      ->delimiter(',');
  sweep_command->add_option("--model", sweep.model, "colour model")->capture_default_str();
  int sweep_size = 0;
  auto* sweep_size_option =
      sweep_command->add_option("--size", sweep_size, "image width and height (default 96)");
  auto* sweep_width = sweep_command->add_option("--width", sweep.width, "image width (default 96)");
  auto* sweep_height = sweep_command->add_option("--height", sweep.height, "image height (default 96)");
  sweep_size_option->excludes(sweep_width)->excludes(sweep_height);
  sweep_command->add_option("--out", sweep.out_dir, "output folder")->required();
  sweep_command->add_flag("-q,--quiet", sweep.quiet, "no progress bar");
  sweep_command->callback([&] {
    sweep.data_dir = data_dir;
    if (sweep_size_option->count()) {
      checkImageSize("sweep", "--size", sweep_size);
      sweep.width = sweep.height = sweep_size;
    }
    if (sweep_width->count()) checkImageSize("sweep", "--width", sweep.width);
    if (sweep_height->count()) checkImageSize("sweep", "--height", sweep.height);
    svr::runSweep(sweep);
  });

  svr::DemoOptions demo;
  int demo_status = 0;
  auto* demo_command = app.add_subcommand(
      "demo", "compare every backend and model on the default scenes; writes report.html");
  demo_command->add_option("--out", demo.out_dir, "report folder")->capture_default_str();
  demo_command->add_flag("--quick", demo.quick, "fewer models, smaller images (for CI)");
  demo_command->add_flag("-q,--quiet", demo.quiet, "no progress bars");
  demo_command->callback([&] {
    demo.data_dir = data_dir;
    demo_status = svr::runDemo(demo);
  });
  // ---- end of the harness ---------------------------------------------------------------------

  // ---- svr design PALETTE --out DIR (the spectral design tool) --------------------------------
  svr::DesignCommandOptions design;
  auto* design_command = app.add_subcommand(
      "design", "design lights and materials from a palette of target colours");
  design_command->add_option("PALETTE", design.palette, "design palette JSON (data/palettes/)")
      ->required()
      ->check(CLI::ExistingFile);
  design_command->add_option("--out", design.out_dir, "output folder")->required();
  design_command->add_flag("--strict", design.strict, "exit with status 2 when a cell misses");
  design_command->add_flag("--no-plots", [&](std::int64_t) { design.plots = false; },
                           "skip spectra.png (matplotlib)");
  design_command->add_flag("-q,--quiet", design.quiet, "no table");
  design_command->callback([&] {
    design.data_dir = data_dir;
    svr::runDesign(design);
  });
  // ---- end of svr design ----------------------------------------------------------------------

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const svr::Error& e) {
    fmt::print(stderr, "svr: error: {}\n", e.what());
    return 2;
  } catch (const svr::Interrupted&) {
    fmt::print(stderr, "svr: interrupted\n");
    return svr::kInterruptedExitCode;
  } catch (const std::exception& e) {
    fmt::print(stderr, "svr: internal error: {}\n", e.what());
    return 3;
  }
  return compare_status != 0 ? compare_status : demo_status;
}
