#include "spectral/design_palette.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "base/error.h"
#include "base/json_reader.h"
#include "spectral/spectrum_spec.h"

namespace svr {

std::string toString(CellKind kind) {
  switch (kind) {
    case CellKind::kColour: return "colour";
    case CellKind::kBlack: return "black";
    case CellKind::kMetamer: return "metamer";
  }
  return "?";
}

Xyz srgbHexToXyz(const std::string& hex) {
  if (hex.size() != 7 || hex[0] != '#')
    throw Error(fmt::format("'{}' is not an sRGB colour of the form #rrggbb", hex));
  Eigen::Vector3d rgb;
  for (int c = 0; c < 3; ++c) {
    int value = 0;
    for (int d = 0; d < 2; ++d) {
      const char ch = hex[1 + 2 * c + d];
      int digit = -1;
      if (ch >= '0' && ch <= '9') digit = ch - '0';
      if (ch >= 'a' && ch <= 'f') digit = ch - 'a' + 10;
      if (ch >= 'A' && ch <= 'F') digit = ch - 'A' + 10;
      if (digit < 0) throw Error(fmt::format("'{}' is not an sRGB colour of the form #rrggbb", hex));
      value = value * 16 + digit;
    }
    rgb[c] = value / 255.0;
  }
  return encodedSrgbToXyz(rgb);
}

Xyz labToXyz(const Lab& lab, const Xyz& white) {
  const double fy = (lab[0] + 16.0) / 116.0;
  const double fx = fy + lab[1] / 500.0;
  const double fz = fy - lab[2] / 200.0;
  constexpr double kDelta = 6.0 / 29.0;
  auto finv = [](double f) { return f > kDelta ? f * f * f : 3 * kDelta * kDelta * (f - 4.0 / 29.0); };
  return {white.x() * finv(fx), white.y() * finv(fy), white.z() * finv(fz)};
}

namespace {

std::vector<DesignSpectrum> readSpectra(const JsonReader& list, const SpectrumLibrary& library,
                                        const std::filesystem::path& base, bool is_light) {
  if (!list.isArray() || list.size() == 0) list.fail("must be a non-empty array");
  std::vector<DesignSpectrum> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const JsonReader item = list.at(i);
    DesignSpectrum s;
    if (item.isObject() && item.contains("free")) {
      s.name = item.at("name").string();
      s.free = item.at("free").boolean();
      if (!s.free) item.at("free").fail("'free' can only be true; give a spectrum otherwise");
      // Lights start flat (E), materials mid grey, unless a starting guess is given.
      if (auto init = item.find("init"))
        s.spectrum = parseSpectrumSpec(*init, library, base);
      else
        s.spectrum = Spectrum::constant(library.grid(), is_light ? 1.0 : 0.5);
      item.rejectUnknownKeys();
    } else {
      s.name = item.isString() ? item.string() : item.at("name").string();
      s.spectrum = parseSpectrumSpec(item, library, base);
    }
    if (!s.spectrum.allFinite()) item.fail("spectrum has non-finite values");
    for (const auto& other : out)
      if (other.name == s.name) item.fail(fmt::format("duplicate name '{}'", s.name));
    out.push_back(std::move(s));
  }
  return out;
}

int indexOf(const std::vector<DesignSpectrum>& list, const JsonReader& name, const char* what) {
  const std::string n = name.string();
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].name == n) return static_cast<int>(i);
  name.fail(fmt::format("'{}' is not a {} of the palette", n, what));
}

}  // namespace

DesignPalette loadDesignPalette(const std::string& path, const SpectrumLibrary& library,
                                const Observer& observer) {
  return parseDesignPalette(JsonReader::parseFile(path), path, library, observer);
}

// The palette's "options" object.
static DesignOptions parseDesignOptions(const JsonReader& options) {
  DesignOptions opt;
  opt.smoothness = options.number("smoothness", opt.smoothness, 0.0, 1e6);
  const std::string bounds = options.string("bounds", "physical");
  if (bounds == "physical")
    opt.bounds = DesignBounds::kPhysical;
  else if (bounds == "artificial")
    opt.bounds = DesignBounds::kArtificial;
  else
    options.at("bounds").fail(fmt::format("'{}': expected 'physical' or 'artificial'", bounds));
  const std::string model = options.string("projection_model", "none");
  if (model != "none") {
    int k = 0;
    if (model.rfind("factor:", 0) != 0 || (k = std::atoi(model.c_str() + 7)) < 3 || k > 16)
      options.at("projection_model").fail(fmt::format("'{}': expected 'none' or 'factor:k', k in 3..16", model));
    opt.projection_k = k;
  }
  opt.projection_weight = options.number("projection_weight", opt.projection_weight, 0.0, 1e6);
  opt.projection_de2000 = options.number("projection_de2000", opt.projection_de2000, 0.0, 100.0);
  opt.projection_rounds = options.integer("projection_rounds", opt.projection_rounds, 1, 1000);
  opt.light_luminance = options.number("light_luminance", opt.light_luminance, 1e-6, 1e6);
  opt.max_iterations = options.integer("max_iterations", opt.max_iterations, 1, 100000);
  opt.miss_de2000 = options.number("miss_de2000", opt.miss_de2000, 0.0);
  opt.black_y = options.number("black_y", opt.black_y, 0.0);
  opt.ridge = options.number("ridge", opt.ridge, 0.0, 1e3);
  opt.split_blocks = options.boolean("split_blocks", opt.split_blocks);
  options.rejectUnknownKeys();
  return opt;
}

DesignPalette parseDesignPalette(const nlohmann::json& json, const std::string& path,
                                 const SpectrumLibrary& library, const Observer& observer) {
  const JsonReader root(json, path);
  if (!root.isObject()) root.fail("expected a JSON object");
  const auto base = std::filesystem::path(path).parent_path();
  for (const char* key : {"description", "name", "lights", "materials", "cells", "metamers",
                          "options"})
    root.find(key);
  root.rejectUnknownKeys();
  DesignPalette p;
  p.description = root.string("description", "");
  p.lights = readSpectra(root.at("lights"), library, base, true);
  p.materials = readSpectra(root.at("materials"), library, base, false);
  for (const auto& l : p.lights)
    for (const auto& m : p.materials)
      if (l.name == m.name)
        root.at("materials").fail(fmt::format("'{}' names both a light and a material", l.name));

  if (auto cells = root.find("cells")) {
    if (!cells->isArray()) cells->fail("must be an array");
    for (std::size_t i = 0; i < cells->size(); ++i) {
      const JsonReader c = cells->at(i);
      if (!c.isObject()) c.fail("expected an object");
      DesignCell cell;
      cell.material = indexOf(p.materials, c.at("material"), "material");
      cell.light = indexOf(p.lights, c.at("light"), "light");
      cell.weight = c.number("weight", 1.0, 0.0, 1e6);
      int forms = 0;
      if (auto v = c.find("srgb")) {
        ++forms;
        try {
          cell.target = srgbHexToXyz(v->string());
        } catch (const Error& e) {
          v->fail(e.what());
        }
      }
      if (auto v = c.find("xyz")) {
        ++forms;
        const auto x = v->numbers(3);
        cell.target = {x[0], x[1], x[2]};
        if (!cell.target.allFinite() || cell.target.minCoeff() < 0) v->fail("expected finite XYZ ≥ 0");
      }
      if (auto v = c.find("lab")) {
        ++forms;
        const auto x = v->numbers(3);
        if (x[0] < 0 || x[0] > 100) v->fail(fmt::format("L* = {} is outside 0..100", x[0]));
        cell.target = labToXyz({x[0], x[1], x[2]}, linearSrgbToXyzMatrix() * Eigen::Vector3d::Ones());
      }
      if (auto v = c.find("like")) {
        // The colour a known reflectance has under a given light (e.g. keep an organ's
        // daylight colour). Under a free light that colour would move with the design.
        ++forms;
        const DesignSpectrum& light = p.lights[cell.light];
        if (light.free) v->fail(fmt::format("'like' needs a given light; '{}' is free", light.name));
        const Spectrum r = parseSpectrumSpec(*v, library, base);
        const Xyz lr = observer.xyz(light.spectrum * r), w = observer.xyz(light.spectrum);
        cell.target = lr / w.y();
      }
      if (auto v = c.find("black")) {
        ++forms;
        if (!v->boolean()) v->fail("'black' can only be true");
        cell.kind = CellKind::kBlack;
        cell.target = Xyz::Zero();
      }
      if (forms != 1) c.fail("give exactly one of 'srgb', 'xyz', 'lab', 'like' or 'black'");
      c.rejectUnknownKeys();
      for (const auto& other : p.cells)
        if (other.material == cell.material && other.light == cell.light)
          c.fail(fmt::format("a second target for material '{}' under light '{}'",
                             p.materials[cell.material].name, p.lights[cell.light].name));
      p.cells.push_back(cell);
    }
  }
  if (auto groups = root.find("metamers")) {
    if (!groups->isArray()) groups->fail("must be an array");
    for (std::size_t i = 0; i < groups->size(); ++i) {
      const JsonReader g = groups->at(i);
      MetamerGroup group;
      group.light = indexOf(p.lights, g.at("light"), "light");
      const JsonReader list = g.at("materials");
      if (!list.isArray() || list.size() < 2) list.fail("must list at least two materials");
      for (std::size_t j = 0; j < list.size(); ++j)
        group.materials.push_back(indexOf(p.materials, list.at(j), "material"));
      group.weight = g.number("weight", 1.0, 0.0, 1e6);
      g.rejectUnknownKeys();
      p.metamers.push_back(group);
    }
  }
  if (p.cells.empty() && p.metamers.empty())
    root.fail("a design palette needs at least one entry in 'cells' or 'metamers'");

  if (auto o = root.find("options")) p.options = parseDesignOptions(*o);
  return p;
}

}  // namespace svr
