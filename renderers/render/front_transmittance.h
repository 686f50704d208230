#pragma once
// Early ray termination across the bricks of a distributed render (design.md §5b). On its own a
// brick behind others cannot see what lies in front of it, so it marches rays that the whole
// render stops early: the engine at 512³ in two bricks took 40 % more samples in all than whole.
// A FrontTransmittance hands a backend, block by block of the image, the transmittance of the
// bricks in front (the product of their own T), and passes the brick's own T on to the bricks
// behind as each block is done. The backend then stops each ray where the whole render stops it
// (max_c T_front,c · T_c < ε) and still returns its own S and T, which composite with the over
// operator as before: the image is the whole render's to float rounding, early termination on.
//
// Blocks are kBlock × kBlock pixels, numbered row-major; a block's transmittance is t_channels
// planes of kBlock² floats, pitch kBlock, whatever part of the block lies in the image.

#include <glm/vec3.hpp>
#include <vector>

#include "renderers/volume/brick_box.h"
#include "renderers/scene/camera.h"

namespace svr {

class LightIndependentImage;

class FrontTransmittance {
 public:
  static constexpr int kBlock = 32;
  static int blocksAcross(int pixels) { return (pixels + kBlock - 1) / kBlock; }

  virtual ~FrontTransmittance() = default;
  // How many blocks the brick renders; the others hold none of its samples and keep S = 0,
  // T = 1.
  virtual int blocks() const = 0;
  // The next block to render, −1 when all have been given: one whose transmittance in front is
  // known, waiting only when none is. Which block comes when may depend on timing; what each
  // block holds does not.
  virtual int next() = 0;
  // The transmittance in front of the brick over a block next() gave, or null where nothing
  // lies in front.
  virtual const float* front(int block) = 0;
  // The brick's image is final over this block: its T goes to the bricks behind.
  virtual void finished(int block, const LightIndependentImage& image) = 0;
  // Every block is finished: waits until what was sent has been taken.
  virtual void done() = 0;
  // The render failed: keeps every promise (the blocks not yet sent go as T = 1, which stops no
  // ray behind) and takes what the bricks in front send, so that no other process waits forever.
  virtual void abandon() = 0;
  // Milliseconds spent waiting in front() so far.
  virtual double waitedMs() const { return 0.0; }
};

// The blocks of a width×height image whose pixels' rays can take a sample this box owns
// (conservative: the projected box's bounding rectangle, a voxel and a pixel wider).
std::vector<int> footprintBlocks(const VoxelBox& own, const Dims& whole,
                                 const glm::dvec3& spacing, const Camera& camera, int width,
                                 int height);

// Block b's transmittance planes copied out of an image (pitch kBlock; 1 outside the image).
void copyBlockTransmittance(const LightIndependentImage& image, int block, float* out);

}  // namespace svr
