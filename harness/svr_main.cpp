// svr: the spectral volume renderer's command line.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>

#include "harness/model_error_command.h"
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
