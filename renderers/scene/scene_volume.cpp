#include "renderers/scene/scene_volume.h"

#include <fmt/format.h>

#include "renderers/volume/memory_budget.h"
#include "renderers/volume/procedural_volume.h"
#include "renderers/volume/volume_brick.h"
#include "base/error.h"

namespace svr {
namespace fs = std::filesystem;

namespace {

Dims cube(int n) { return {n, n, n}; }

}  // namespace

SceneVolume loadSceneVolume(const JsonReader& spec, const fs::path& base_dir,
                            const VolumeLoadOptions& options) {
  if (!spec.isObject()) spec.fail("expected {\"file\": …} or {\"procedural\": …}");
  if (spec.contains("file") == spec.contains("procedural"))
    spec.fail("give exactly one of 'file' or 'procedural'");
  if (auto file = spec.find("file")) {
    const std::string path = (base_dir / file->string()).string();
    VolumeLoadOptions opts = options;
    if (auto raw = spec.find("raw")) {
      RawLayout layout;
      const auto dims = raw->at("dims").numbers(3);
      for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1 || dims[a] > 1e9 || dims[a] != static_cast<int>(dims[a]))
          raw->at("dims").fail(fmt::format("dimension {} is {}; dims must be integers ≥ 1", a, dims[a]));
        layout.dims[a] = static_cast<int>(dims[a]);
      }
      try {
        layout.type = parseScalarType(raw->at("type").string());
      } catch (const Error& e) {
        raw->at("type").fail(e.what());
      }
      const std::string endian = raw->string("endian", "little");
      if (endian != "little" && endian != "big")
        raw->at("endian").fail(fmt::format("'{}' is neither little nor big", endian));
      layout.endian = endian == "big" ? Endian::kBig : Endian::kLittle;
      if (auto s = raw->find("spacing")) {
        const auto v = s->numbers(3);
        for (int a = 0; a < 3; ++a)
          if (!(v[a] > 0)) s->fail(fmt::format("spacing {} is {}; it must be > 0", a, v[a]));
        layout.spacing = {v[0], v[1], v[2]};
      }
      layout.header_bytes = static_cast<std::uint64_t>(raw->number("header_bytes", 0, 0, 1e15));
      layout.gzip = raw->boolean("gzip", false);
      raw->rejectUnknownKeys();
      opts.raw = layout;
    }
    if (auto s = spec.find("spacing")) {
      const auto v = s->numbers(3);
      for (int a = 0; a < 3; ++a)
        if (!(v[a] > 0) || !std::isfinite(v[a]))
          s->fail(fmt::format("spacing {} is {}; it must be finite and > 0", a, v[a]));
      opts.spacing = glm::dvec3(v[0], v[1], v[2]);
    }
    spec.rejectUnknownKeys();
    try {
      return {loadVolume(path, opts), path};
    } catch (const Error& e) {
      // A spacing given for a format that states its own: the key is what to fix.
      if (opts.spacing && std::string(e.what()).find("states its own spacing") != std::string::npos)
        spec.at("spacing").fail(e.what());
      throw;
    }
  }
  const std::string kind = spec.at("procedural").string();
  const int size = spec.integer("size", 64, 2, 1024);
  const glm::dvec3 spacing(1.0);
  // Procedural volumes are float32 and, like files, must fit the budget before a voxel is made
  // (1024³ would be 4 GiB).
  const Dims dims = kind == "phantom" ? cube(kPhantomSize) : cube(size);
  checkMemoryBudget(volumeBytes({dims[0], dims[1], dims[2]}, ScalarType::kFloat32, spec.where()),
                    options.memory_budget,
                    fmt::format("{}: procedural {} {}", spec.where(), kind,
                                describeShape(dims, ScalarType::kFloat32)));
  SceneVolume out;
  if (kind == "marschner_lobb") {
    out.volume = marschnerLobbVolume(size);
  } else if (kind == "slab") {
    const double fraction = spec.number("thickness", 0.5, 0.0, 1.0);
    out.volume = slabVolume(cube(size), spacing, fraction * (size - 1));
  } else if (kind == "sphere") {
    const double fraction = spec.number("radius", 0.8, 0.0, 1.0);
    out.volume = sphereVolume(cube(size), spacing, fraction * 0.5 * (size - 1));
  } else if (kind == "shells") {
    const int shells = spec.integer("shells", 3, 1, 64);
    std::vector<double> radii;
    for (int i = 1; i <= shells; ++i) radii.push_back(0.45 * (size - 1) * i / shells);
    out.volume = nestedShellsVolume(cube(size), spacing, radii);
  } else if (kind == "phantom") {
    out.volume = phantomVolume();
  } else {
    spec.at("procedural")
        .fail(fmt::format("unknown procedural volume '{}'; expected marschner_lobb, slab, sphere, "
                          "shells or phantom", kind));
  }
  spec.rejectUnknownKeys();
  out.source = fmt::format("procedural {} ({}³)", kind, out.volume.dims()[0]);
  // A brick of a procedural volume: made whole (closed forms are cheap), then cut.
  if (options.brick) out.volume = cropToBrick(out.volume, options.brick(out.volume.dims()));
  if (options.lattice) out.volume = latticeOf(out.volume, *options.lattice);
  return out;
}

}  // namespace svr
