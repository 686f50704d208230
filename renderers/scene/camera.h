#pragma once
// Cameras (design.md §7): an orbit about the volume centre (azimuth about +z, elevation from the
// xy-plane, distance) or an explicit look-at; field of view 0 = orthographic. Images have row 0
// at the top and pixel centres at +0.5.

#include <glm/vec3.hpp>

namespace svr {

struct Ray {
  glm::dvec3 origin;
  glm::dvec3 direction;  // unit length
};

struct Camera {
  glm::dvec3 eye{0.0, -1.0, 0.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fov_degrees = 0.0;  // vertical; 0 = orthographic
  double ortho_height = 2.0; // world height of the orthographic view

  static Camera orbit(double azimuth_deg, double elevation_deg, double distance,
                      double fov_deg, double ortho_height);
  bool orthographic() const { return fov_degrees <= 0.0; }
};

// A view of a base camera by orbit angles about its target, at its distance, with a zoom relative
// to its framing (the sweep's and the viewer's views): one formula for every caller, so a view
// at the base camera's own angles and zoom 1 frames as the base camera does.
struct OrbitView {
  double azimuth = 0.0, elevation = 0.0;  // degrees: about +z, and from the xy-plane
  double zoom = 1.0;                      // > 0; 2 shows half the height
};
OrbitView orbitViewOf(const Camera& base);
// Throws svr::Error for a zoom that is not > 0 and finite.
Camera orbitCamera(const Camera& base, const OrbitView& view);

// Rays for a width×height image; one instance per render, cheap to query per pixel.
class RayGenerator {
 public:
  RayGenerator(const Camera& camera, int width, int height);
  Ray ray(double px, double py) const;  // px, py in pixels (centre of pixel x is x + 0.5)
  const glm::dvec3& forward() const { return forward_; }
  // A pixel at image-plane offsets (u, v) in [−1, 1] looks along forward + u·right·halfWidth +
  // v·up·halfHeight (perspective; orthographic rays start there instead, parallel to forward).
  const glm::dvec3& right() const { return right_; }
  const glm::dvec3& up() const { return up_; }
  double halfWidth() const { return half_w_; }
  double halfHeight() const { return half_h_; }

 private:
  Camera camera_;
  int width_, height_;
  glm::dvec3 forward_, right_, up_;
  double half_w_, half_h_;
};

}  // namespace svr
