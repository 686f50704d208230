#pragma once
// The over operator on light-independent images (design.md §5b): an image in front of another is
// S = S_f + T_f ⊙ S_b, T = T_f ⊙ T_b, componentwise over the k channels (one scalar T for
// achromatic absorbers), like every product of the factor model. A distributed render
// composites its bricks' images with it in visibility order and relights once afterwards, so
// the light still costs nothing across processes. Associative (not commutative): any grouping
// of an ordered sequence gives the same image to float rounding, which lets binary swap and
// reductions over ranks order their work freely.

#include <cstddef>
#include <span>
#include <vector>

#include "spectral/light_independent_image.h"

namespace svr {

// back := front over back. Throws svr::Error when sizes or channel counts differ or an image
// is not float.
void compositeOver(const LightIndependentImage& front, LightIndependentImage& back);

// The same on pixel-interleaved samples (k S values, then the T values, per pixel), what ranks
// exchange: back[i] := front[i] over back[i] for `pixels` pixels.
void compositeOverInterleaved(const float* front, float* back, std::size_t pixels, int k,
                              int t_channels);

// Planar ⇄ pixel-interleaved, for the exchange.
std::vector<float> interleavedSamples(const LightIndependentImage& image);
LightIndependentImage fromInterleaved(std::span<const float> samples, int width, int height,
                                      int k, int t_channels);

}  // namespace svr
