#pragma once
// The order in which the images of a distributed render's bricks (renderers/volume/volume_brick.h)
// composite for a camera (design.md §5b).

#include <glm/vec3.hpp>
#include <vector>

#include "renderers/scene/camera.h"
#include "renderers/volume/volume_brick.h"

namespace svr {

// The order in which the bricks' images composite front to back for this camera (indices into
// `bricks`): at every kd plane the side the eye is on comes first (orthographic: the side the
// rays come from). volume_spacing and whole dims place the planes in world space.
std::vector<int> visibilityOrder(const std::vector<KdBrick>& bricks, const Camera& camera,
                                 const Dims& whole, const glm::dvec3& spacing);

}  // namespace svr
