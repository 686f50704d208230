#pragma once
// FrontTransmittance over MPI (renderers/render/front_transmittance.h): each rank renders the
// image blocks its brick's footprint covers, receives over each block the own T of every brick
// in front whose footprint covers it, and sends its own T to every brick behind whose footprint
// covers it. Only ranks in front are waited on, so the dependencies run one way and the ranks
// cannot deadlock; the receives are posted up front and the sends do not block.
//
// Order (next()): first the blocks nothing lies in front of that bricks behind wait for, so that
// those start early; then, of the blocks that wait on the bricks in front, any whose
// transmittance has come; while none has, the blocks nobody waits on; only then does it wait.

#include <mpi.h>

#include <chrono>
#include <vector>

#include "renderers/render/front_transmittance.h"
#include "renderers/volume/volume_brick.h"

namespace svr {

class MpiFrontTransmittance final : public FrontTransmittance {
 public:
  // `depth_order`: the ranks front to back for this camera. Collective over `comm`.
  MpiFrontTransmittance(MPI_Comm comm, const std::vector<KdBrick>& bricks,
                        const std::vector<int>& depth_order, const Dims& whole,
                        const glm::dvec3& spacing, const Camera& camera, int width, int height,
                        int t_channels);
  ~MpiFrontTransmittance() override;

  int blocks() const override { return blocks_; }
  int next() override;
  const float* front(int block) override;
  void finished(int block, const LightIndependentImage& image) override;
  void done() override;
  void abandon() override;
  double waitedMs() const override { return waited_ms_; }

 private:
  // What comes from the bricks in front over one block: their T, in depth order, and its
  // receives, requests_[first, first + buffers.size()).
  struct Incoming {
    std::size_t first = 0;
    std::vector<std::vector<float>> buffers;
  };
  bool arrived(int block);
  void send(int block, std::vector<float> transmittance);
  void waitForAll();

  MPI_Comm comm_ = MPI_COMM_NULL;
  int planes_size_ = 0;  // floats of one block's T
  int blocks_ = 0, given_ = 0;
  std::vector<int> ahead_;    // nothing in front, bricks behind wait for them: first
  std::vector<int> waiting_;  // waiting on bricks in front, in block order
  std::vector<int> filler_;   // nothing in front, nobody waits for them
  std::vector<Incoming> incoming_;        // by block
  std::vector<MPI_Request> requests_;     // every receive, completed ones MPI_REQUEST_NULL
  std::vector<std::vector<int>> behind_;  // by block: ranks behind whose footprint holds it
  std::vector<bool> sent_;                // by block: its T has gone to the bricks behind
  std::vector<std::vector<float>> outgoing_;
  std::vector<MPI_Request> sends_;
  std::vector<float> product_;
  double waited_ms_ = 0;
  bool closed_ = false;
};

}  // namespace svr
