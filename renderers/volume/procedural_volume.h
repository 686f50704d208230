#pragma once
// Volumes with closed forms, for tests and benches (after Open VKL's procedural volumes): each
// is a float32 Volume sampled at its voxel centres, Volume::worldPosition(i, j, k), so it is
// centred at the origin like every volume; beside each are the analytic functions (values,
// gradients, chord lengths) that tests compare renderers against.

#include <glm/vec3.hpp>
#include <vector>

#include "renderers/volume/volume.h"

namespace svr {

// --- Marschner & Lobb, "An evaluation of reconstruction filters for volume rendering",
// IEEE Visualization 1994: ρ(x,y,z) = (1 − sin(πz/2) + α(1 + ρr(√(x²+y²)))) / (2(1 + α)),
// ρr(r) = cos(2π fM cos(πr/2)), fM = 6, α = 0.25, over [−1, 1]³; values lie in [0, 1]. Most of
// its energy sits just below the Nyquist rate of a 41³ sampling, so it shows filter errors.
inline constexpr double kMarschnerLobbFM = 6.0;
inline constexpr double kMarschnerLobbAlpha = 0.25;
double marschnerLobb(glm::dvec3 p);
glm::dvec3 marschnerLobbGradient(glm::dvec3 p);
// n³ samples spanning [−1, 1]³ exactly (spacing 2/(n − 1)); n ≥ 2, else svr::Error.
Volume marschnerLobbVolume(int n);

// --- A homogeneous slab: 1 where |z| ≤ thickness/2 (world units), 0 elsewhere.
Volume slabVolume(Dims dims, glm::dvec3 spacing, double thickness);
// Length of a line with this direction (any length, not zero) inside the infinite slab:
// thickness·|d|/|d.z|; infinity for a line parallel to the slab (assumed inside it).
double slabChordLength(double thickness, glm::dvec3 direction);

// --- A homogeneous box: 1 where |x| ≤ half.x, |y| ≤ half.y and |z| ≤ half.z.
Volume boxVolume(Dims dims, glm::dvec3 spacing, glm::dvec3 half_size);
// Length of the line origin + t·direction (all t) inside that box; 0 if it misses.
double boxChordLength(glm::dvec3 half_size, glm::dvec3 origin, glm::dvec3 direction);

// --- A homogeneous ball: 1 where |p| ≤ radius.
Volume sphereVolume(Dims dims, glm::dvec3 spacing, double radius);
// Chord of a line at distance b (the impact parameter) from the centre: 2√(R² − b²), 0 if b ≥ R.
double sphereChordLength(double radius, double b);

// --- Nested shells: radii strictly increasing and > 0; value i + 1 where
// radii[i − 1] < |p| ≤ radii[i] (radii[−1] = 0), so the innermost ball is 1, the outermost
// shell radii.size(), and outside 0. Throws svr::Error for bad radii.
Volume nestedShellsVolume(Dims dims, glm::dvec3 spacing, const std::vector<double>& radii);
int nestedShellIndex(const std::vector<double>& radii, double r);
// Chord inside the shell inner < |p| ≤ outer for impact parameter b (both sides of the centre).
double shellChordLength(double inner, double outer, double b);
// ∫ value along a line at impact parameter b: Σ (i + 1) · chord of shell i.
double nestedShellsLineIntegral(const std::vector<double>& radii, double b);

// --- A label map: 64³ voxels, spacing 1, so world coordinates run −31.5 … 31.5:
//   0  background, outside the body;
//   1  "body": the ball |p| ≤ 28;
//   2  a box, centre (−12, 0, 0), half size (6, 6, 14): exactly 12·12·28 = 4032 voxels;
//   3  a ball, centre (12, 0, 0), radius 8;
//   4  a small ball, centre (0, 12, 10), radius 4.
// Labels 2, 3 and 4 lie inside the body and do not touch one another.
inline constexpr int kPhantomSize = 64;
int phantomLabel(glm::dvec3 p);
Volume phantomVolume();

}  // namespace svr
