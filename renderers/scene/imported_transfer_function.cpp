#include "renderers/scene/imported_transfer_function.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "base/error.h"
#include "spectral/design_palette.h"
#include "spectral/design_solver.h"

namespace svr {

namespace {

constexpr int kSamplesPerSegment = 32;
constexpr double kMaxAlpha = 0.999;
constexpr double kOpacityTolerance = 0.002;  // of the σ share, when thinning the curve

Xyz srgbWhite() { return encodedSrgbToXyz(Eigen::Vector3d::Ones()); }

// x of every control point and kSamplesPerSegment − 1 between each two.
template <typename Point>
std::vector<double> denseSamples(const std::vector<Point>& points) {
  std::vector<double> xs;
  for (std::size_t i = 0; i < points.size(); ++i) {
    xs.push_back(points[i].x);
    if (i + 1 == points.size()) break;
    for (int s = 1; s < kSamplesPerSegment; ++s)
      xs.push_back(points[i].x + (points[i + 1].x - points[i].x) * s / kSamplesPerSegment);
  }
  return xs;
}

// The fewest samples (always the first and last) such that a straight line between two kept
// ones is close enough at every sample between: close(a, m, b, t) for sample m, a fraction t of
// the way from a to b. Greedy: from each kept sample, the farthest one that still fits.
template <typename Close>
std::vector<std::size_t> linearKnots(const std::vector<double>& xs, const Close& close) {
  const auto fits = [&](std::size_t a, std::size_t b) {
    for (std::size_t m = a + 1; m < b; ++m)
      if (!close(a, m, b, (xs[m] - xs[a]) / (xs[b] - xs[a]))) return false;
    return true;
  };
  std::vector<std::size_t> knots{0};
  while (knots.back() + 1 < xs.size()) {
    std::size_t b = knots.back() + 1;
    while (b + 1 < xs.size() && fits(knots.back(), b + 1)) ++b;
    knots.push_back(b);
  }
  return knots;
}

// Knots between which a linear blend of XYZ stays within `tolerance` ΔE2000 of every sample.
std::vector<std::size_t> colourKnots(const std::vector<double>& xs, const std::vector<Xyz>& xyz,
                                     double tolerance) {
  const Xyz white = srgbWhite();
  return linearKnots(xs, [&](std::size_t a, std::size_t m, std::size_t b, double t) {
    return deltaE2000(xyzToLab((1 - t) * xyz[a] + t * xyz[b], white), xyzToLab(xyz[m], white)) <=
           tolerance;
  });
}

// One reflectance per knot colour, designed under the light (physical bounds: 0 ≤ r ≤ 1). The
// colours do not interact, so each is its own small design problem (one joint problem of n free
// spectra costs far more than n small ones).
std::vector<NamedSpectrum> designReflectances(const std::vector<Xyz>& targets,
                                              const NamedSpectrum& light,
                                              const Observer& observer,
                                              std::vector<double>& de2000) {
  std::vector<NamedSpectrum> out(targets.size());
  de2000.assign(targets.size(), 0.0);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    DesignPalette design;
    design.description = "a colour of an imported map";
    design.lights.push_back({light.name, false, light.spectrum});
    design.materials.push_back(
        {fmt::format("map {}", i), true, Spectrum::constant(observer.grid(), 0.5)});
    design.cells.push_back({0, 0, CellKind::kColour, targets[i], 1.0});
    const DesignResult result = designPalette(design, observer);
    out[i] = result.materials.front();
    de2000[i] = result.cells.front().de2000;
  }
  return out;
}

double sigmaOf(double alpha, double unit_distance) {
  return -std::log1p(-std::min(alpha, kMaxAlpha)) / unit_distance;
}

// The opacity curve as shares of the largest σ, thinned to the points a linear curve needs.
std::vector<std::pair<double, double>> opacityCurve(const ColourMap& map, double unit_distance,
                                                    double& sigma_max) {
  const std::vector<double> xs =
      map.opacity.empty() ? std::vector<double>{map.colours.front().x} : denseSamples(map.opacity);
  std::vector<double> sigma;
  for (const double x : xs) sigma.push_back(sigmaOf(map.alphaAt(x), unit_distance));
  sigma_max = *std::max_element(sigma.begin(), sigma.end());
  const auto share = [&](std::size_t i) { return sigma_max > 0 ? sigma[i] / sigma_max : 0.0; };
  std::vector<std::pair<double, double>> curve;
  for (const std::size_t k :
       linearKnots(xs, [&](std::size_t a, std::size_t m, std::size_t b, double t) {
         return std::abs((1 - t) * share(a) + t * share(b) - share(m)) <= kOpacityTolerance;
       }))
    curve.emplace_back(xs[k], share(k));
  return curve;
}

}  // namespace

Lab transferFunctionLab(const TransferFunction& tf, double x, const Spectrum& light,
                        const Observer& observer) {
  Eigen::VectorXd reflectance = Eigen::VectorXd::Zero(observer.grid().count);
  for (const auto& [index, weight] : tf.materialWeights(x))
    reflectance += weight * tf.materials[static_cast<std::size_t>(index)].reflectance.values();
  const Xyz white = observer.xyz(light);
  const Xyz xyz = observer.xyz(Spectrum(observer.grid(), light.values().cwiseProduct(reflectance)));
  return xyzToLab(xyz / white.y(), white / white.y());
}

ImportedTransferFunction importTransferFunction(const ColourMap& map,
                                                const SpectrumLibrary& library,
                                                const Observer& observer,
                                                const ImportOptions& options) {
  if (!(options.unit_distance > 0) || !std::isfinite(options.unit_distance))
    throw Error(fmt::format("{}: unit distance {} must be finite and > 0", map.source,
                            options.unit_distance));
  const NamedSpectrum light{options.light, library.get(options.light)};
  const std::vector<double> xs = denseSamples(map.colours);
  std::vector<Xyz> xyz;
  for (const double x : xs) xyz.push_back(encodedSrgbToXyz(map.colourAt(x)));
  const std::vector<std::size_t> knots = colourKnots(xs, xyz, options.blend_de2000);

  ImportedTransferFunction out;
  std::vector<Xyz> targets;
  for (const std::size_t k : knots) targets.push_back(xyz[k] / srgbWhite().y());
  std::vector<double> de2000;
  const std::vector<NamedSpectrum> reflectances =
      designReflectances(targets, light, observer, de2000);
  const auto curve = opacityCurve(map, options.unit_distance, out.sigma);
  for (std::size_t i = 0; i < knots.size(); ++i) {
    Material m;
    m.name = reflectances[i].name;
    m.reflectance = reflectances[i].spectrum;
    m.extinction = out.sigma;
    m.specular = options.specular;
    out.tf.materials.push_back(std::move(m));
    out.tf.points.push_back({xs[knots[i]], static_cast<int>(i)});
    out.knots.push_back({xs[knots[i]], map.colourAt(xs[knots[i]]), de2000[i]});
  }
  out.tf.opacity = curve;
  for (const ColourPoint& p : map.colours)
    out.control_point_de2000.push_back(
        deltaE2000(transferFunctionLab(out.tf, p.x, light.spectrum, observer), srgbLab(p.srgb)));
  return out;
}

}  // namespace svr
