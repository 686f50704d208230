#include "renderers/render/brick_order.h"

#include <algorithm>
#include <numeric>

namespace svr {
namespace {

// Whether brick a's image lies in front of brick b's: decided at the first plane that separates
// them (they share the path above it).
bool inFront(const KdBrick& a, const KdBrick& b, const Camera& camera, const RayGenerator& rays,
             const Dims& whole, const glm::dvec3& spacing) {
  for (std::size_t i = 0; i < std::min(a.path.size(), b.path.size()); ++i) {
    if (a.path[i].low == b.path[i].low) continue;
    const int axis = a.path[i].axis;
    // The plane in world space (design.md §7: voxel i at (i − (dims − 1)/2) · spacing).
    const double plane = (a.path[i].plane - 0.5 * (whole[axis] - 1)) * spacing[axis];
    const bool low_first = camera.orthographic() ? rays.forward()[axis] >= 0.0
                                                 : camera.eye[axis] <= plane;
    return a.path[i].low == low_first;
  }
  return false;
}

}  // namespace

std::vector<int> visibilityOrder(const std::vector<KdBrick>& bricks, const Camera& camera,
                                 const Dims& whole, const glm::dvec3& spacing) {
  const RayGenerator rays(camera, 1, 1);
  std::vector<int> order(bricks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return inFront(bricks[a], bricks[b], camera, rays, whole, spacing);
  });
  return order;
}

}  // namespace svr
