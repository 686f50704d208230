#include "renderers/scene/colour_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "spectral/colorimetry.h"
#include "spectral/design_palette.h"

namespace svr {

namespace {

Xyz srgbWhite() { return encodedSrgbToXyz(Eigen::Vector3d::Ones()); }

Eigen::Vector3d labToSrgb(const Eigen::Vector3d& lab) {
  const Eigen::Vector3d linear = xyzToLinearSrgbMatrix() * labToXyz(lab, srgbWhite());
  return {srgbEncode(std::clamp(linear.x(), 0.0, 1.0)), srgbEncode(std::clamp(linear.y(), 0.0, 1.0)),
          srgbEncode(std::clamp(linear.z(), 0.0, 1.0))};
}

Eigen::Vector3d rgbToHsv(const Eigen::Vector3d& c) {
  const double hi = c.maxCoeff(), lo = c.minCoeff(), d = hi - lo;
  double h = 0;
  if (d > 0) {
    if (hi == c.x()) h = std::fmod((c.y() - c.z()) / d + 6, 6);
    else if (hi == c.y()) h = (c.z() - c.x()) / d + 2;
    else h = (c.x() - c.y()) / d + 4;
  }
  return {h / 6, hi > 0 ? d / hi : 0, hi};
}

Eigen::Vector3d hsvToRgb(const Eigen::Vector3d& hsv) {
  const double h = std::fmod(hsv.x() * 6 + 6, 6), s = hsv.y(), v = hsv.z();
  const double c = v * s, x = c * (1 - std::abs(std::fmod(h, 2) - 1)), m = v - c;
  const int sector = static_cast<int>(h);
  const Eigen::Vector3d rgb = sector == 0 ? Eigen::Vector3d(c, x, 0)
                              : sector == 1 ? Eigen::Vector3d(x, c, 0)
                              : sector == 2 ? Eigen::Vector3d(0, c, x)
                              : sector == 3 ? Eigen::Vector3d(0, x, c)
                              : sector == 4 ? Eigen::Vector3d(x, 0, c)
                                            : Eigen::Vector3d(c, 0, x);
  return rgb + Eigen::Vector3d::Constant(m);
}

// Moreland's Msh space ("Diverging Color Maps for Scientific Visualization", 2009): Lab in
// polar form, so that a diverging map passes through an unsaturated white between two hues.
Eigen::Vector3d labToMsh(const Eigen::Vector3d& lab) {
  const double m = lab.norm();
  return {m, m > 0 ? std::acos(std::clamp(lab.x() / m, -1.0, 1.0)) : 0.0,
          std::atan2(lab.z(), lab.y())};
}

Eigen::Vector3d mshToLab(const Eigen::Vector3d& msh) {
  return {msh.x() * std::cos(msh.y()), msh.x() * std::sin(msh.y()) * std::cos(msh.z()),
          msh.x() * std::sin(msh.y()) * std::sin(msh.z())};
}

// The hue an unsaturated end takes so that the blend does not swing through other hues.
double adjustHue(const Eigen::Vector3d& saturated, double m_unsaturated) {
  if (saturated.x() >= m_unsaturated) return saturated.z();
  const double spin = saturated.y() * std::sqrt(m_unsaturated * m_unsaturated -
                                                saturated.x() * saturated.x()) /
                      (saturated.x() * std::sin(saturated.y()));
  return saturated.z() > -std::numbers::pi / 3 ? saturated.z() + spin : saturated.z() - spin;
}

Eigen::Vector3d divergingBlend(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  Eigen::Vector3d m1 = labToMsh(srgbLab(a)), m2 = labToMsh(srgbLab(b));
  if (m1.y() > 0.05 && m2.y() > 0.05 && std::abs(m1.z() - m2.z()) > std::numbers::pi / 3) {
    const double mid = std::max({m1.x(), m2.x(), 88.0});
    if (t < 0.5) m2 = {mid, 0, 0}, t *= 2;
    else m1 = {mid, 0, 0}, t = 2 * t - 1;
  }
  if (m1.y() < 0.05 && m2.y() > 0.05) m1.z() = adjustHue(m2, m1.x());
  else if (m2.y() < 0.05 && m1.y() > 0.05) m2.z() = adjustHue(m1, m2.x());
  return labToSrgb(mshToLab((1 - t) * m1 + t * m2));
}

Eigen::Vector3d blend(ColourSpace space, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      double t) {
  switch (space) {
    case ColourSpace::kRgb: return (1 - t) * a + t * b;
    case ColourSpace::kStep: return a;
    case ColourSpace::kLab: return labToSrgb((1 - t) * srgbLab(a) + t * srgbLab(b));
    case ColourSpace::kDiverging: return divergingBlend(a, b, t);
    case ColourSpace::kHsv: {
      Eigen::Vector3d ha = rgbToHsv(a), hb = rgbToHsv(b);
      // The shorter way round the hue circle.
      if (hb.x() - ha.x() > 0.5) ha.x() += 1;
      else if (ha.x() - hb.x() > 0.5) hb.x() += 1;
      return hsvToRgb((1 - t) * ha + t * hb);
    }
  }
  return a;
}

// ParaView's segment shape: x in [0, 1] between two points, bent so that the midpoint reaches
// the mean, then from linear (sharpness 0) towards a step (sharpness 1) by a Hermite curve.
double shapedAlpha(const OpacityPoint& a, const OpacityPoint& b, double x) {
  const double m = std::clamp(a.midpoint, 1e-5, 1 - 1e-5), s = a.sharpness;
  x = x < m ? 0.5 * x / m : 0.5 + 0.5 * (x - m) / (1 - m);
  if (s > 0.99) return x < 0.5 ? a.alpha : b.alpha;
  if (s < 0.01) return (1 - x) * a.alpha + x * b.alpha;
  x = x < 0.5 ? 0.5 * std::pow(2 * x, 1 + 10 * s) : 1 - 0.5 * std::pow(2 * (1 - x), 1 + 10 * s);
  const double x2 = x * x, x3 = x2 * x;
  const double h1 = 2 * x3 - 3 * x2 + 1, h2 = -2 * x3 + 3 * x2, h3 = x3 - 2 * x2 + x, h4 = x3 - x2;
  const double slope = (1 - s) * (b.alpha - a.alpha);
  return std::clamp(h1 * a.alpha + h2 * b.alpha + (h3 + h4) * slope, 0.0, 1.0);
}

// The points either side of x, strictly inside the points' range, and x's place between them.
template <typename Point>
struct Segment {
  const Point& a;
  const Point& b;
  double t;
};
template <typename Point>
Segment<Point> segmentAt(const std::vector<Point>& points, double x) {
  const auto hi = std::upper_bound(points.begin(), points.end(), x,
                                   [](double v, const Point& p) { return v < p.x; });
  return {*(hi - 1), *hi, (x - (hi - 1)->x) / (hi->x - (hi - 1)->x)};
}

}  // namespace

Lab srgbLab(const Eigen::Vector3d& srgb) { return xyzToLab(encodedSrgbToXyz(srgb), srgbWhite()); }

Eigen::Vector3d ColourMap::colourAt(double x) const {
  if (x <= colours.front().x) return colours.front().srgb;
  if (x >= colours.back().x) return colours.back().srgb;
  const auto [a, b, t] = segmentAt(colours, x);
  return blend(space, a.srgb, b.srgb, t);
}

double ColourMap::alphaAt(double x) const {
  if (opacity.empty()) return 1.0;
  if (x <= opacity.front().x) return opacity.front().alpha;
  if (x >= opacity.back().x) return opacity.back().alpha;
  const auto [a, b, t] = segmentAt(opacity, x);
  return shapedAlpha(a, b, t);
}

ColourMap ColourMap::rescaled(double lo, double hi) const {
  ColourMap out = *this;
  const double from = colours.front().x, to = colours.back().x;
  const double scale = to > from ? (hi - lo) / (to - from) : 0.0;
  const auto move = [&](double x) { return to > from ? lo + (x - from) * scale : lo; };
  for (ColourPoint& p : out.colours) p.x = move(p.x);
  for (OpacityPoint& p : out.opacity) p.x = move(p.x);
  return out;
}

}  // namespace svr
