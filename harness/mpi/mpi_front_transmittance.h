#pragma once
// FrontTransmittance over MPI (renderers/core/front_transmittance.h): each rank renders the
// image blocks its brick's footprint covers, receives over each block the own T of every brick
// in front whose footprint covers it, and sends its own T to every brick behind whose footprint
// covers it. Only ranks in front are waited on, so the dependencies run one way and the ranks
// cannot deadlock; the receives are posted up front and the sends do not block.
//
// Order: a rank first renders the blocks nothing lies in front of, those that bricks behind wait
// for first, then the blocks that wait on the bricks in front, in block order — the order in
// which those are produced — so that the bricks behind start while the ones in front still work.

#include <mpi.h>

#include <chrono>
#include <vector>

#include "renderers/core/front_transmittance.h"
#include "renderers/core/volume_brick.h"

namespace svr {

class MpiFrontTransmittance final : public FrontTransmittance {
 public:
  // `depth_order`: the ranks front to back for this camera. Collective over `comm`.
  MpiFrontTransmittance(MPI_Comm comm, const std::vector<KdBrick>& bricks,
                        const std::vector<int>& depth_order, const Dims& whole,
                        const glm::dvec3& spacing, const Camera& camera, int width, int height,
                        int t_channels);
  ~MpiFrontTransmittance() override;

  const std::vector<int>& order() const override { return order_; }
  const float* front(int block) override;
  void finished(int block, const LightIndependentImage& image) override;
  void done() override;
  void abandon() override;
  double waitedMs() const override { return waited_ms_; }

 private:
  struct Incoming {
    int block;
    std::vector<MPI_Request> requests;        // one per brick in front, in depth order
    std::vector<std::vector<float>> buffers;  // their T
    bool taken = false;
  };
  void send(int block, std::vector<float> transmittance);
  void waitForAll();

  MPI_Comm comm_ = MPI_COMM_NULL;
  int planes_size_ = 0;  // floats of one block's T
  std::vector<int> order_;
  std::vector<Incoming> incoming_;        // by block index into order_
  std::vector<int> incoming_of_block_;    // block → index into incoming_, −1: none
  std::vector<std::vector<int>> behind_;  // block → ranks behind whose footprint holds it
  std::vector<bool> sent_;                // block → its T has gone to the bricks behind
  std::vector<std::vector<float>> outgoing_;
  std::vector<MPI_Request> sends_;
  std::vector<float> product_;
  double waited_ms_ = 0;
  bool closed_ = false;
};

}  // namespace svr
