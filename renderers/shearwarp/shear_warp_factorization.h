#pragma once
// The factorisation of an orthographic view into a shear of the volume slices and a 2D affine
// warp (Lacroute & Levoy 1994, §3), in voxel index space so anisotropic spacing is handled by
// the same algebra.
//
// With d the view direction in voxel units and c the principal axis (largest |d_c|), the ray
// through a point reaches slice k (index along c) at in-slice voxel coordinates
//   q_i = a_i + s_i·k,   q_j = a_j + s_j·k,   s = d / d_c   (|s_i|, |s_j| ≤ 1),
// where (a_i, a_j) is where it crosses slice 0. The intermediate image is the (a_i, a_j) plane
// sampled at `scale` pixels per voxel: pixel (u, v) has its centre at
//   a_i = u / scale + offset_i,   a_j = v / scale + offset_j,
// so a slice is a translated copy of the voxel grid on it (the shear), and the final image is
// an affine image of the intermediate one (the warp).

#include <glm/vec3.hpp>

#include "renderers/scene/camera.h"
#include "renderers/volume/volume.h"

namespace svr::shearwarp {

struct ShearWarpFactorization {
  int axis = 2;                 // principal axis c
  int axis_i = 0, axis_j = 1;   // in-slice axes (as in AxisEncoding)
  bool increasing = true;       // front-to-back order is k = 0, 1, … (else n_k − 1 down)
  double shear_i = 0.0, shear_j = 0.0;    // s_i, s_j: voxels of shift per slice
  double offset_i = 0.0, offset_j = 0.0;  // a of intermediate pixel 0
  int scale = 1;                          // intermediate pixels per voxel
  int width = 0, height = 0;              // intermediate image (along i, j)
  // Samples per voxel slice along c (sampleBetweenSlices): slice k of an encoding with m slice
  // samples lies at voxel position k / m along c.
  int slice_samples = 1;
  // World length of the ray between two samples, √(1 + s_i² + s_j²) in isotropic voxels over
  // slice_samples: the sample spacing that opacity and transmission are corrected for.
  double slice_spacing_world = 1.0;
  // Final-image pixel (px, py) (continuous, centres at +0.5) → intermediate (u, v):
  // u = warp_u[0] + warp_u[1]·px + warp_u[2]·py, likewise v.
  double warp_u[3] = {0, 0, 0}, warp_v[3] = {0, 0, 0};
};

// Throws svr::Error for a perspective camera (perspective shear-warp is not implemented).
// axis_i/axis_j follow AxisEncoding's choice for the principal axis.
ShearWarpFactorization factorizeView(const Camera& camera, int width, int height,
                                     const Dims& dims, const glm::dvec3& spacing, int scale);

// The intermediate pixels per voxel (1 … max) that keep the intermediate image at least as
// fine as the final one in every direction: the final pixels a voxel spans where the warp
// magnifies most (1 / the smaller singular value of its Jacobian at `view`'s scale), rounded
// up. `view`: factorised at scale 1.
int supersampleForScreen(const ShearWarpFactorization& view, int max);

// The view sampled m times per voxel slice along the principal axis: the samples between voxel
// slices are trilinear (rle_volume.h), a world step of slice_spacing_world / m.
void sampleBetweenSlices(ShearWarpFactorization& view, int m);

// The fewest samples per voxel slice (1 … max) that put the ray's samples no farther apart
// than step_world, the render step the raycaster takes.
int sliceSamplesForStep(const ShearWarpFactorization& view, double step_world, int max);

}  // namespace svr::shearwarp
