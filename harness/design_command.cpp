#include "harness/design_command.h"

#include <CLI/CLI.hpp>
#include <memory>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/command.h"
#include "harness/image_files.h"
#include "base/atomic_file.h"
#include "spectral/colorimetry.h"
#include "spectral/design_solver.h"
#include "base/data_dir.h"
#include "base/error.h"
#include "spectral/spectrum_library.h"


namespace svr {
namespace fs = std::filesystem;

namespace {

std::string spectraCsv(const DesignResult& r) {
  std::string text = "wavelength_nm";
  for (const auto* list : {&r.lights, &r.materials})
    for (const auto& s : *list) text += "," + s.name;
  text += "\n";
  const WavelengthGrid grid = r.lights.front().spectrum.grid();
  for (int i = 0; i < grid.count; ++i) {
    text += fmt::format("{}", grid.wavelength(i));
    for (const auto* list : {&r.lights, &r.materials})
      for (const auto& s : *list) text += fmt::format(",{:.9g}", s.spectrum[i]);
    text += "\n";
  }
  return text;
}

std::array<std::uint8_t, 3> toSrgb8(const Xyz& xyz) {
  const Eigen::Vector3d rgb = xyzToLinearSrgbMatrix() * xyz;
  std::array<std::uint8_t, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<std::uint8_t>(
        std::lround(255.0 * srgbEncode(std::clamp(rgb[c], 0.0, 1.0))));
  return out;
}

// Paper Fig. 5: a grid of materials (rows) × lights (columns); a constrained cell shows its
// target on the left and the achieved colour on the right, a free cell only the achieved colour.
void writeSwatches(const DesignPalette& p, const DesignResult& r, const Observer& observer,
                   const std::string& path) {
  constexpr int kCell = 64, kGap = 6;
  const int rows = static_cast<int>(p.materials.size()), cols = static_cast<int>(p.lights.size());
  const int width = cols * (kCell + kGap) + kGap, height = rows * (kCell + kGap) + kGap;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3, 96);
  const CmfMatrix cmf = normalisedCmf(observer);
  for (int m = 0; m < rows; ++m)
    for (int j = 0; j < cols; ++j) {
      const Xyz achieved =
          relativeXyz(cmf, r.lights[j].spectrum.values(), r.materials[m].spectrum.values());
      const CellReport* cell = nullptr;
      for (const auto& c : r.cells)
        if (c.material == p.materials[m].name && c.light == p.lights[j].name) cell = &c;
      const auto right = toSrgb8(achieved);
      const auto left = cell ? toSrgb8(cell->target) : right;
      for (int y = 0; y < kCell; ++y)
        for (int x = 0; x < kCell; ++x) {
          const auto& c = x < kCell / 2 ? left : right;
          const std::size_t at = (static_cast<std::size_t>(kGap + m * (kCell + kGap) + y) * width +
                                  kGap + j * (kCell + kGap) + x) * 3;
          std::copy(c.begin(), c.end(), rgb.begin() + static_cast<std::ptrdiff_t>(at));
        }
    }
  writeSrgbPng(rgb, width, height, path);
}

nlohmann::json xyzJson(const Xyz& x) { return {x.x(), x.y(), x.z()}; }

}  // namespace

int runDesign(const DesignCommandOptions& o) {
  const WavelengthGrid grid = WavelengthGrid::standard();
  const auto library = SpectrumLibrary::load(o.data_dir, grid);
  const auto observer = Observer::cie1931(o.data_dir, grid);
  const DesignPalette palette = loadDesignPalette(o.palette, library, observer);
  const DesignResult r = designPalette(palette, observer);

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) throw Error(fmt::format("{}: cannot create folder: {}", o.out_dir, ec.message()));
  const fs::path out(o.out_dir);
  writeTextAtomically(out / "spectra.csv", spectraCsv(r));

  nlohmann::json plain;
  plain["description"] = fmt::format("designed by svr design from {}", o.palette);
  for (const auto* list : {&r.lights, &r.materials}) {
    auto& arr = plain[list == &r.lights ? "lights" : "materials"];
    arr = nlohmann::json::array();
    for (const auto& s : *list) arr.push_back({{"name", s.name}, {"csv", "spectra.csv"}, {"column", s.name}});
  }
  writeTextAtomically(out / "palette.json", plain.dump(2) + "\n");

  nlohmann::json design;
  design["cells"] = nlohmann::json::array();
  for (const auto& c : r.cells)
    design["cells"].push_back({{"material", c.material},
                               {"light", c.light},
                               {"kind", toString(c.kind)},
                               {"target_xyz", xyzJson(c.target)},
                               {"achieved_xyz", xyzJson(c.achieved)},
                               {"de2000", c.de2000},
                               {"residual", c.residual},
                               {"miss", c.miss}});
  design["objective"] = r.objective;
  design["unconstrained_objective"] = r.unconstrained_objective;
  design["iterations"] = r.iterations;
  design["converged"] = r.converged;
  design["history"] = r.history;
  design["misses"] = r.misses;
  if (palette.options.projection_k > 0) {
    // Every light × material: what the scene's factor:k keeps of it (TOG 2009's F(E) term).
    nlohmann::json projection = nlohmann::json::array();
    for (const auto& p : r.projection)
      projection.push_back({{"material", p.material}, {"light", p.light}, {"de2000", p.de2000}});
    design["projection"] = {{"model", fmt::format("factor:{}", palette.options.projection_k)},
                            {"rounds", r.projection_rounds},
                            {"cells", projection}};
  }
  writeTextAtomically(out / "design.json", design.dump(2) + "\n");

  writeSwatches(palette, r, observer, (out / "palette.png").string());
  if (o.plots) {
    const std::string cmd = fmt::format(
        "/usr/bin/python3 '{}/plot_spectra.py' '{}' '{}' {} 2>&1", scriptDir(),
        (out / "spectra.csv").string(), (out / "spectra.png").string(), r.lights.size());
    if (std::system(cmd.c_str()) != 0)
      fmt::print(stderr, "design: warning: spectra.png not written (needs python3-matplotlib)\n");
  }

  if (!o.quiet) {
    fmt::print("{:<14} {:<10} {:<8} {:>26} {:>26} {:>8} {:>9}\n", "material", "light", "kind",
               "target XYZ", "achieved XYZ", "ΔE2000", "residual");
    for (const auto& c : r.cells)
      fmt::print("{:<14} {:<10} {:<8} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.2f} "
                 "{:>9.2e}{}\n",
                 c.material, c.light, toString(c.kind), c.target.x(), c.target.y(), c.target.z(),
                 c.achieved.x(), c.achieved.y(), c.achieved.z(), c.de2000, c.residual,
                 c.miss ? "  MISS" : "");
    fmt::print("objective {:.6g} (unconstrained first solve {:.6g}), {} iteration(s), {}\n",
               r.objective, r.unconstrained_objective, r.iterations,
               r.converged ? "converged" : "iteration cap reached");
    if (!r.projection.empty()) {
      const auto worst = *std::max_element(r.projection.begin(), r.projection.end(),
                                           [](const auto& a, const auto& b) { return a.de2000 < b.de2000; });
      double mean = 0;
      for (const auto& p : r.projection) mean += p.de2000 / r.projection.size();
      fmt::print("projection onto factor:{} ({} subspace round(s)): every light × material mean "
                 "ΔE2000 {:.3f}, worst {:.3f} ({} under {})\n",
                 palette.options.projection_k, r.projection_rounds, mean, worst.de2000,
                 worst.material, worst.light);
    }
  }
  for (const auto& m : r.misses) fmt::print(stderr, "design: miss: {}\n", m);
  if (o.strict && !r.misses.empty())
    throw Error(fmt::format("design: {}: {} cell(s) miss their targets (--strict)", o.palette,
                            r.misses.size()));
  return 0;
}

namespace commands {

CommandEntry design() {
  return {"design", "design lights and materials from a palette of target colours",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<DesignCommandOptions>();
            sub.add_option("PALETTE", o->palette, "design palette JSON (data/palettes/)")
                ->required()
                ->check(CLI::ExistingFile);
            sub.add_option("--out", o->out_dir, "output folder")->required();
            sub.add_flag("--strict", o->strict, "exit with status 2 when a cell misses");
            sub.add_flag("--no-plots", [o](std::int64_t) { o->plots = false; },
                         "skip spectra.png (matplotlib)");
            sub.add_flag("-q,--quiet", o->quiet, "no table");
            runOnParse(sub, context, o, &runDesign);
          }};
}

}  // namespace commands

}  // namespace svr
