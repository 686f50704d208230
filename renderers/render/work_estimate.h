#pragma once
// A render's work, estimated before any brick is read (design.md §5b), so that a distributed
// render's kd-split can share out time rather than voxels. With the transmittance in front
// passed between bricks (render/front_transmittance.h) a brick stops its rays where the whole
// render does, so the bricks near the eye do most of the work: the engine at 512³, split at its
// middle plane, left 64 % of it to the front brick. The estimate marches rays through a coarse
// lattice of the volume (VolumeLoadOptions::lattice), classified as the render will be, front
// to back with early termination, and counts each sample the ray caster would shade (α > 0) at
// its cell; empty space, which the ray caster skips, counts nothing.

#include "renderers/volume/brick_box.h"
#include "renderers/scene/camera.h"
#include "renderers/classification/classification.h"

namespace svr {

// Samples per axis of the lattice an estimate reads (a 128³ lattice reads 1/64 of a 512³
// volume). A plane is found to within a fraction of a lattice cell, and on the 512³ engine at 2
// ranks one x column holds about 1 % of the render: with 64 samples the plane fell at x = 304,
// where the front brick had 3 % more render instructions than the back one (callgrind) and the
// back rank spun waiting for its blocks; with 128 at x = 309, the back brick 2.4 % more, the two
// ranks' instructions summing to the single-rank render's within 0.1 %. The estimate then takes
// about 125 ms (64: about 80).
inline constexpr int kWorkLatticeSamples = 128;

// `coarse`: a lattice of the volume (its spacing keeps the grid's extent), classified for this
// render's transfer function. `rays_across`: probe rays along the image's longer side.
WorkGrid estimateWork(const ClassifiedVolume& coarse, const Camera& camera, int width, int height,
                      double termination, int rays_across = 128);

}  // namespace svr
