#include "harness/import_tf_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/error.h"
#include "base/atomic_file.h"
#include "harness/command.h"
#include "renderers/scene/colour_map.h"
#include "renderers/scene/imported_transfer_function.h"
#include "renderers/volume/volume_io.h"

namespace svr {

namespace fs = std::filesystem;

namespace {

ColourMap readMap(const ImportTfOptions& o) {
  const std::string ext = fs::path(o.map).extension().string();
  if (ext == ".json") return readParaViewColourMap(o.map, o.preset);
  if (ext == ".vp") return readSlicerVolumeProperty(o.map);
  throw Error(fmt::format("{}: expected a ParaView preset (.json) or a Slicer volume property "
                          "(.vp)",
                          o.map));
}

ColourMap rescale(const ColourMap& map, const ImportTfOptions& o) {
  if (o.range.empty()) return map;
  if (o.range == "data") {
    const auto [lo, hi] = loadVolume(o.volume).valueRange();
    return map.rescaled(lo, hi);
  }
  double lo = 0, hi = 0;
  char comma = 0;
  std::istringstream in(o.range);
  if (!(in >> lo >> comma >> hi) || comma != ',' || !(hi > lo) || !in.eof())
    throw Error(fmt::format("--range: '{}' is not LO,HI with LO < HI, nor 'data'", o.range));
  return map.rescaled(lo, hi);
}

nlohmann::json sceneJson(const ImportTfOptions& o, const ColourMap& map,
                         const ImportedTransferFunction& imported) {
  nlohmann::json materials = nlohmann::json::object();
  for (const Material& m : imported.tf.materials) {
    const WavelengthGrid& grid = m.reflectance.grid();
    nlohmann::json wavelengths = nlohmann::json::array(), values = nlohmann::json::array();
    for (int i = 0; i < grid.count; ++i) {
      wavelengths.push_back(grid.wavelength(i));
      values.push_back(m.reflectance.values()[i]);
    }
    materials[m.name] = {{"reflectance", {{"wavelengths", wavelengths}, {"values", values}}},
                         {"opacity", m.extinction},
                         {"specular", m.specular}};
  }
  nlohmann::json points = nlohmann::json::array(), opacity = nlohmann::json::array();
  for (const MaterialPoint& p : imported.tf.points)
    points.push_back({p.value, imported.tf.materials[static_cast<std::size_t>(p.material)].name});
  for (const auto& [x, share] : imported.tf.opacity) opacity.push_back({x, share});
  const fs::path out_dir = fs::absolute(o.out).parent_path();
  return {{"description",
           fmt::format("'{}' from {}, imported by svr import-tf: colours matched under {}, α per "
                       "{} world units",
                       map.name, fs::path(o.map).filename().string(), o.light, o.unit_distance)},
          {"volume", {{"file", fs::relative(fs::absolute(o.volume), out_dir).string()}}},
          {"materials", materials},
          {"transfer_function", {{"type", "scalar"}, {"points", points}, {"opacity", opacity}}},
          {"lights", {o.light}}};
}

}  // namespace

int runImportTf(const ImportTfOptions& o) {
  if (!fs::is_regular_file(o.volume) && !fs::is_directory(o.volume))
    throw Error(fmt::format("--volume: {}: no such file", o.volume));
  const ColourMap map = rescale(readMap(o), o);
  const WavelengthGrid grid = WavelengthGrid::standard();
  const auto library = SpectrumLibrary::load(o.data_dir, grid);
  if (!library.contains(o.light)) throw Error(fmt::format("--light: unknown light '{}'", o.light));
  const auto observer = Observer::cie1931(o.data_dir, grid);
  ImportOptions options;
  options.unit_distance = o.unit_distance;
  options.light = o.light;
  options.specular = o.specular;
  const ImportedTransferFunction imported = importTransferFunction(map, library, observer, options);
  writeTextAtomically(o.out, sceneJson(o, map, imported).dump(1) + "\n");
  if (!o.quiet) {
    fmt::print("{}: '{}', {} colour points → {} materials, σ {:.4g} per world unit\n", o.map,
               map.name, map.colours.size(), imported.tf.materials.size(), imported.sigma);
    fmt::print("  {:>12}  {:>22}  {}\n", "x", "map sRGB", "ΔE2000 under " + o.light);
    for (std::size_t i = 0; i < map.colours.size(); ++i) {
      const auto& c = map.colours[i];
      fmt::print("  {:>12.6g}  ({:.3f}, {:.3f}, {:.3f})  {:.3f}\n", c.x, c.srgb.x(), c.srgb.y(),
                 c.srgb.z(), imported.control_point_de2000[i]);
    }
    fmt::print("wrote {}\n", o.out);
  }
  return 0;
}

namespace commands {

CommandEntry import_tf() {
  return {"import-tf", "a ParaView (.json) or Slicer (.vp) colour map as an svr scene",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<ImportTfOptions>();
            sub.add_option("MAP", o->map, "ParaView JSON preset or Slicer .vp")
                ->required()
                ->check(CLI::ExistingFile);
            sub.add_option("--volume", o->volume, "the scene's volume (any format svr reads)")
                ->required();
            sub.add_option("--out", o->out, "scene file to write")->required();
            sub.add_option("--preset", o->preset, "ParaView: the preset's Name, of several");
            sub.add_option("--range", o->range,
                           "move the map's x range onto LO,HI, or onto the volume's value "
                           "range: data");
            sub.add_option("--unit-distance", o->unit_distance,
                           "world length over which α is the map's opacity")
                ->check(CLI::PositiveNumber)
                ->capture_default_str();
            sub.add_option("--light", o->light, "library light the colours are matched under")
                ->capture_default_str();
            sub.add_option("--specular", o->specular, "specular weight of every material")
                ->check(CLI::NonNegativeNumber);
            sub.add_flag("-q,--quiet", o->quiet, "no table");
            runOnParse(sub, context, o, &runImportTf);
          }};
}

}  // namespace commands

}  // namespace svr
