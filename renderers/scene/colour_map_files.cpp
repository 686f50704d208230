// Reading colour maps from ParaView's JSON presets and 3D Slicer's .vp files (colour_map.h).
// Every value is checked: a wrong count, a NaN, a colour outside 0…1 or an x that does not
// increase is an error naming the file and the field.
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.h"
#include "base/json_reader.h"
#include "renderers/scene/colour_map.h"

namespace svr {

namespace {

// One numbers field: finite, x (every `stride`-th from 0) strictly increasing.
void checkIncreasing(const std::vector<double>& flat, std::size_t stride, const std::string& where) {
  for (std::size_t i = 0; i < flat.size(); ++i)
    if (!std::isfinite(flat[i]))
      throw Error(fmt::format("{}: value {} is {}; values must be finite", where, i, flat[i]));
  for (std::size_t i = stride; i < flat.size(); i += stride)
    if (!(flat[i] > flat[i - stride]))
      throw Error(fmt::format("{}: x must increase, but point {} is at {} after {}", where,
                              i / stride, flat[i], flat[i - stride]));
}

void checkUnit(double v, const std::string& where, std::size_t point, const char* what) {
  if (!(v >= 0 && v <= 1))
    throw Error(fmt::format("{}: point {}'s {} is {}; expected 0 … 1", where, point, what, v));
}

std::vector<ColourPoint> colourPoints(const std::vector<double>& flat, const std::string& where) {
  if (flat.size() < 4 || flat.size() % 4 != 0)
    throw Error(fmt::format("{}: holds {} numbers; expected x, r, g, b for each of one or more "
                            "points",
                            where, flat.size()));
  checkIncreasing(flat, 4, where);
  std::vector<ColourPoint> out;
  for (std::size_t i = 0; i < flat.size(); i += 4) {
    for (int c = 0; c < 3; ++c)
      checkUnit(flat[i + 1 + c], where, i / 4, std::array{"red", "green", "blue"}[c]);
    out.push_back({flat[i], {flat[i + 1], flat[i + 2], flat[i + 3]}});
  }
  return out;
}

ColourSpace colourSpace(const std::string& name, const std::string& where) {
  if (name == "RGB") return ColourSpace::kRgb;
  if (name == "HSV") return ColourSpace::kHsv;
  if (name == "Lab" || name == "CIELAB") return ColourSpace::kLab;
  if (name == "Diverging") return ColourSpace::kDiverging;
  if (name == "Step") return ColourSpace::kStep;
  throw Error(fmt::format("{}: ColorSpace '{}' is not one of RGB, HSV, Lab, CIELAB, Diverging, "
                          "Step",
                          where, name));
}

std::vector<double> flatNumbers(const JsonReader& r) {
  if (!r.isArray()) r.fail("expected an array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < r.size(); ++i) out.push_back(r.at(i).number());
  return out;
}

ColourMap paraViewPreset(const JsonReader& preset, const std::string& path) {
  ColourMap map;
  map.source = path;
  map.name = preset.string("Name", std::filesystem::path(path).stem().string());
  map.space = colourSpace(preset.string("ColorSpace", "RGB"), preset.where() + ": ColorSpace");
  map.colours = colourPoints(flatNumbers(preset.at("RGBPoints")), preset.at("RGBPoints").where());
  if (auto points = preset.find("Points")) {
    const std::vector<double> flat = flatNumbers(*points);
    const std::string where = points->where();
    if (flat.size() < 4 || flat.size() % 4 != 0)
      throw Error(fmt::format("{}: holds {} numbers; expected x, α, midpoint, sharpness for each "
                              "point",
                              where, flat.size()));
    checkIncreasing(flat, 4, where);
    for (std::size_t i = 0; i < flat.size(); i += 4) {
      checkUnit(flat[i + 1], where, i / 4, "opacity");
      checkUnit(flat[i + 2], where, i / 4, "midpoint");
      checkUnit(flat[i + 3], where, i / 4, "sharpness");
      map.opacity.push_back({flat[i], flat[i + 1], flat[i + 2], flat[i + 3]});
    }
  }
  return map;
}

}  // namespace

ColourMap readParaViewColourMap(const std::string& path, const std::string& preset) {
  const nlohmann::json json = JsonReader::parseFile(path);
  const JsonReader root(json, path);
  if (root.isObject()) return paraViewPreset(root, path);
  if (!root.isArray() || root.size() == 0)
    root.fail("expected a ParaView preset: an object, or an array of them");
  std::string names;
  for (std::size_t i = 0; i < root.size(); ++i) {
    const JsonReader p = root.at(i);
    if (!p.isObject()) p.fail("expected a preset object");
    const std::string name = p.contains("Name") ? p.at("Name").string() : "";
    if ((preset.empty() && root.size() == 1) || (!preset.empty() && name == preset))
      return paraViewPreset(p, path);
    names += (names.empty() ? "" : ", ") + fmt::format("'{}'", name);
  }
  throw Error(fmt::format("{}: {} presets ({}); {}", path, root.size(), names,
                          preset.empty() ? "name one with \"preset\""
                                         : fmt::format("none is named '{}'", preset)));
}

ColourMap readSlicerVolumeProperty(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(fmt::format("{}: cannot open", path));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  if (lines.size() < 9)
    throw Error(fmt::format("{}: holds {} lines; a Slicer volume property has 9 (interpolation, "
                            "shade, diffuse, ambient, specular, power, scalar opacity, gradient "
                            "opacity, colour)",
                            path, lines.size()));
  // "N v1 … vN": the count, then the values.
  const auto function = [&](std::size_t line, std::size_t stride, const char* what) {
    const std::string where = fmt::format("{}: line {} ({})", path, line + 1, what);
    std::istringstream words(lines[line]);
    std::vector<double> values;
    for (std::string word; words >> word;) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0')
        throw Error(fmt::format("{}: '{}' is not a number", where, word));
      values.push_back(v);
    }
    if (values.empty() || values[0] != std::floor(values[0]) ||
        values[0] != static_cast<double>(values.size() - 1) ||
        static_cast<std::size_t>(values[0]) % stride != 0 || values[0] < stride)
      throw Error(fmt::format("{}: starts with the count {} but holds {} values after it; expected "
                              "{} per point",
                              where, values.empty() ? 0.0 : values[0],
                              values.empty() ? 0 : values.size() - 1, stride));
    values.erase(values.begin());
    checkIncreasing(values, stride, where);
    return values;
  };
  ColourMap map;
  map.source = path;
  map.name = std::filesystem::path(path).stem().string();
  const std::vector<double> alpha = function(6, 2, "scalar opacity");
  for (std::size_t i = 0; i < alpha.size(); i += 2) {
    checkUnit(alpha[i + 1], fmt::format("{}: line 7 (scalar opacity)", path), i / 2, "opacity");
    map.opacity.push_back({alpha[i], alpha[i + 1]});
  }
  function(7, 2, "gradient opacity");  // checked; svr's opacity does not depend on the gradient
  map.colours = colourPoints(function(8, 4, "colour"), fmt::format("{}: line 9 (colour)", path));
  return map;
}

}  // namespace svr
