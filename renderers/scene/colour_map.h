#pragma once
// A colour and opacity map as other tools keep them (issue 44): ParaView's exported JSON
// presets and 3D Slicer's volume property (.vp) files. Colours are sRGB (encoded, 0…1) at
// control points, interpolated in the map's colour space; opacity is α per unit distance at
// control points, with ParaView's midpoint and sharpness shaping each segment. The map is turned
// into svr materials by imported_transfer_function.h.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace svr {

struct ColourPoint {
  double x;
  Eigen::Vector3d srgb;  // encoded sRGB, each in [0, 1]
};

struct OpacityPoint {
  double x;
  double alpha;            // in [0, 1]
  double midpoint = 0.5;   // where the segment to the next point reaches the mean (0…1)
  double sharpness = 0.0;  // 0: linear, 1: a step at the midpoint
};

enum class ColourSpace { kRgb, kHsv, kLab, kDiverging, kStep };

struct ColourMap {
  std::string name;   // the preset's Name, or the file's name
  std::string source;  // the file, for messages
  ColourSpace space = ColourSpace::kRgb;
  std::vector<ColourPoint> colours;    // x strictly increasing, at least one
  std::vector<OpacityPoint> opacity;   // x strictly increasing; empty: opaque everywhere

  // Encoded sRGB at x, interpolated as the map's tool does (ends held outside the points).
  Eigen::Vector3d colourAt(double x) const;
  // α at x (ends held; 1 when the map has no opacity points).
  double alphaAt(double x) const;
  // The same map with every x moved from [colours.front().x, colours.back().x] onto [lo, hi]
  // (ParaView rescales a preset to the data range the same way).
  ColourMap rescaled(double lo, double hi) const;
};

// Encoded sRGB as CIELAB against the sRGB white (D65, Y = 1): how far two map colours are apart.
Eigen::Vector3d srgbLab(const Eigen::Vector3d& srgb);

// ParaView's JSON (an exported preset: an array of objects, or one object) with "RGBPoints"
// (flat x, r, g, b), optional "Points" (flat x, α, midpoint, sharpness) and "ColorSpace"
// ("RGB", "HSV", "Lab", "CIELAB", "Diverging", "Step"). `preset` picks one of several by Name
// (empty: the file must hold one). Throws svr::Error naming the file and field.
ColourMap readParaViewColourMap(const std::string& path, const std::string& preset = "");
// 3D Slicer's .vp: interpolation, shade, diffuse, ambient, specular, specular power, then the
// scalar opacity ("N x α …"), gradient opacity and colour ("N x r g b …") functions, a line each.
ColourMap readSlicerVolumeProperty(const std::string& path);

}  // namespace svr
