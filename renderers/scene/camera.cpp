#include "renderers/scene/camera.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "base/error.h"

namespace svr {

Camera Camera::orbit(double azimuth_deg, double elevation_deg, double distance, double fov_deg,
                     double ortho_height) {
  constexpr double deg = std::numbers::pi / 180.0;
  const double az = azimuth_deg * deg, el = elevation_deg * deg;
  Camera c;
  c.eye = distance * glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                std::sin(el));
  c.target = glm::dvec3(0.0);
  // Looking straight down or up, +z cannot be "up": use the direction of azimuth 90° instead.
  c.up = std::abs(std::cos(el)) < 1e-9 ? glm::dvec3(-std::sin(az), std::cos(az), 0.0)
                                       : glm::dvec3(0.0, 0.0, 1.0);
  c.fov_degrees = fov_deg;
  c.ortho_height = ortho_height;
  return c;
}

OrbitView orbitViewOf(const Camera& base) {
  const glm::dvec3 offset = base.eye - base.target;
  const double distance = glm::length(offset);
  if (!(distance > 0)) throw Error("camera: eye and target coincide");
  constexpr double deg = 180.0 / std::numbers::pi;
  return {std::atan2(offset.y, offset.x) * deg,
          std::asin(std::clamp(offset.z / distance, -1.0, 1.0)) * deg, 1.0};
}

Camera orbitCamera(const Camera& base, const OrbitView& view) {
  if (!(view.zoom > 0) || !std::isfinite(view.zoom))
    throw Error(fmt::format("camera: zoom {} must be > 0", view.zoom));
  const double distance = glm::length(base.eye - base.target);
  Camera c = Camera::orbit(view.azimuth, view.elevation, distance, base.fov_degrees,
                   base.ortho_height / view.zoom);
  c.eye += base.target;
  c.target = base.target;
  if (!base.orthographic()) {
    // Perspective: zoom narrows the view as it shrinks an orthographic one.
    constexpr double deg = std::numbers::pi / 180.0;
    c.fov_degrees = 2.0 * std::atan(std::tan(0.5 * base.fov_degrees * deg) / view.zoom) / deg;
  }
  return c;
}

RayGenerator::RayGenerator(const Camera& camera, int width, int height)
    : camera_(camera), width_(width), height_(height) {
  const glm::dvec3 view = camera.target - camera.eye;
  if (!(glm::length(view) > 0))
    throw Error("camera: eye and target coincide");
  forward_ = glm::normalize(view);
  const glm::dvec3 r = glm::cross(forward_, camera.up);
  if (!(glm::length(r) > 1e-12)) throw Error("camera: up is parallel to the view direction");
  right_ = glm::normalize(r);
  up_ = glm::cross(right_, forward_);
  const double aspect = static_cast<double>(width) / height;
  if (camera.orthographic()) {
    half_h_ = 0.5 * camera.ortho_height;
  } else {
    if (!(camera.fov_degrees < 179.0))
      throw Error(fmt::format("camera: field of view {}° must be below 179°", camera.fov_degrees));
    half_h_ = std::tan(0.5 * camera.fov_degrees * std::numbers::pi / 180.0);
  }
  half_w_ = half_h_ * aspect;
}

Ray RayGenerator::ray(double px, double py) const {
  const double u = (2.0 * px / width_ - 1.0) * half_w_;
  const double v = (1.0 - 2.0 * py / height_) * half_h_;
  if (camera_.orthographic())
    return {camera_.eye + u * right_ + v * up_, forward_};
  return {camera_.eye, glm::normalize(forward_ + u * right_ + v * up_)};
}

}  // namespace svr
