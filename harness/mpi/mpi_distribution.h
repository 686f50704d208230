#pragma once
// RenderDistribution over MPI (design.md §5b): one brick of a kd-split per rank, the whole
// volume's ranges by MPI_Allreduce, failures agreed by an all-reduce of the first failing rank
// and a broadcast of its message, and the k-channel images composited in visibility order.
//
// Compositing: binary swap (Ma et al. 1994) on MPI_Sendrecv when the rank count is a power of
// two — each of log₂N rounds exchanges half the pixels a rank still holds, so a rank sends
// about image × (1 − 1/N) in all whatever N, then MPI_Gatherv brings the pieces to rank 0 —
// and otherwise an MPI_Reduce with a non-commutative user operation over a communicator ordered
// by depth (MPI applies it in rank order), which is simple and right for the small, odd counts
// where binary swap does not apply. docs/distributed.md has the numbers.

#include <mpi.h>

#include <optional>
#include <vector>

#include "harness/render_distribution.h"
#include "renderers/volume/volume_brick.h"
#include "base/error.h"

namespace svr {

class MpiDistribution final : public RenderDistribution {
 public:
  explicit MpiDistribution(MPI_Comm comm);
  int rank() const { return rank_; }
  int size() const { return size_; }

  void balance(const WorkGrid* on_writer) override;
  VolumeBrick brick(const Dims& whole) override;
  std::pair<double, double> wholeRange(std::pair<double, double> local) override;
  FieldRange wholeField(const FieldRange& local) override;
  std::unique_ptr<FrontTransmittance> frontTransmittance(const Camera& camera, int width,
                                                         int height, int t_channels,
                                                         const glm::dvec3& spacing) override;
  LightIndependentImage composite(const LightIndependentImage& local, const Camera& camera,
                                  const glm::dvec3& spacing) override;
  nlohmann::json gather(const nlohmann::json& local) override;
  bool writes() const override { return rank_ == 0; }
  int processes() const override { return size_; }
  void agree(const std::exception_ptr& failure) override;

  // "binary swap" or "reduce": how composite() combines images at this rank count.
  const char* compositing() const;

 private:
  // The pixels [begin, end) each depth position holds after binary swap.
  std::vector<std::pair<std::size_t, std::size_t>> swapRegions(std::size_t pixels) const;
  std::vector<float> binarySwap(MPI_Comm depth, int position, std::vector<float> samples,
                                int stride, int k, int t_channels) const;
  std::vector<float> reduceInDepthOrder(MPI_Comm depth, std::vector<float> samples, int stride,
                                        int k, int t_channels) const;

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  Dims whole_{0, 0, 0};
  std::vector<KdBrick> bricks_;
  std::optional<WorkGrid> work_;
};

// Thrown by agree() on every rank when one failed: its message names that rank.
struct AgreedFailure : Error {
  using Error::Error;
};

}  // namespace svr
