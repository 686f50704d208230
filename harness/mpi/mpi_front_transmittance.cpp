#include "harness/mpi/mpi_front_transmittance.h"

#include <fmt/format.h>

#include <algorithm>

#include "harness/mpi/mpi_check.h"
#include "base/elapsed.h"
#include "base/error.h"

namespace svr {
MpiFrontTransmittance::MpiFrontTransmittance(MPI_Comm comm, const std::vector<KdBrick>& bricks,
                                             const std::vector<int>& depth_order,
                                             const Dims& whole, const glm::dvec3& spacing,
                                             const Camera& camera, int width, int height,
                                             int t_channels) {
  // Its own communicator: block numbers are the tags, apart from every other message.
  checkMpi(MPI_Comm_dup(comm, &comm_), "MPI_Comm_dup");
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  const int ranks = static_cast<int>(bricks.size());
  const int blocks = blocksAcross(width) * blocksAcross(height);
  planes_size_ = t_channels * kBlock * kBlock;

  // Every rank's footprint, the same on every rank.
  std::vector<std::vector<char>> covers(ranks, std::vector<char>(blocks, 0));
  for (int r = 0; r < ranks; ++r)
    for (int b : footprintBlocks(bricks[r].own, whole, spacing, camera, width, height))
      covers[r][b] = 1;
  const auto me = std::find(depth_order.begin(), depth_order.end(), rank) - depth_order.begin();
  std::vector<std::vector<int>> in_front(blocks);
  behind_.assign(blocks, {});
  for (std::ptrdiff_t p = 0; p < ranks; ++p) {
    const int r = depth_order[p];
    if (r == rank) continue;
    for (int b = 0; b < blocks; ++b)
      if (covers[rank][b] && covers[r][b]) (p < me ? in_front[b] : behind_[b]).push_back(r);
  }

  incoming_.assign(blocks, {});
  sent_.assign(blocks, true);
  for (int b = 0; b < blocks; ++b) {
    if (!covers[rank][b]) continue;
    ++blocks_;
    sent_[b] = false;
    if (in_front[b].empty()) {
      (behind_[b].empty() ? filler_ : ahead_).push_back(b);
      continue;
    }
    waiting_.push_back(b);
    Incoming& in = incoming_[b];
    in.first = requests_.size();
    in.buffers.assign(in_front[b].size(), std::vector<float>(planes_size_));
    for (std::size_t i = 0; i < in_front[b].size(); ++i) {
      MPI_Request request;
      checkMpi(MPI_Irecv(in.buffers[i].data(), planes_size_, MPI_FLOAT, in_front[b][i], b, comm_,
                      &request),
            "MPI_Irecv");
      requests_.push_back(request);
    }
  }
  product_.resize(planes_size_);
}

MpiFrontTransmittance::~MpiFrontTransmittance() {
  try {
    abandon();  // nothing left to do after done(); a render that never ran keeps its promises
  } catch (...) {
    MPI_Abort(MPI_COMM_WORLD, 2);  // a rank could be left waiting: stop the job instead
  }
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

bool MpiFrontTransmittance::arrived(int block) {
  const Incoming& in = incoming_[block];
  int flag = 0;
  checkMpi(MPI_Testall(static_cast<int>(in.buffers.size()), requests_.data() + in.first, &flag,
                    MPI_STATUSES_IGNORE),
        "MPI_Testall");
  return flag != 0;
}

int MpiFrontTransmittance::next() {
  if (given_ == blocks_) return -1;
  const auto take = [this](std::vector<int>& from, std::size_t i) {
    const int b = from[i];
    from.erase(from.begin() + static_cast<std::ptrdiff_t>(i));
    ++given_;
    return b;
  };
  for (;;) {
    if (!ahead_.empty()) return take(ahead_, 0);
    for (std::size_t i = 0; i < waiting_.size(); ++i)
      if (arrived(waiting_[i])) return take(waiting_, i);
    if (!filler_.empty()) return take(filler_, 0);
    // Every block left waits on the bricks in front: until any of their T comes.
    const auto t0 = std::chrono::steady_clock::now();
    int index = 0;
    checkMpi(MPI_Waitany(static_cast<int>(requests_.size()), requests_.data(), &index,
                      MPI_STATUS_IGNORE),
          "MPI_Waitany");
    waited_ms_ += msSince(t0);
    if (index == MPI_UNDEFINED) throw Error("front transmittance: a block was never received");
  }
}

const float* MpiFrontTransmittance::front(int block) {
  const Incoming& in = incoming_[block];
  if (in.buffers.empty()) return nullptr;
  // The product in depth order, the same rounding on every run.
  std::copy(in.buffers[0].begin(), in.buffers[0].end(), product_.begin());
  for (std::size_t i = 1; i < in.buffers.size(); ++i)
    for (int j = 0; j < planes_size_; ++j) product_[j] *= in.buffers[i][j];
  return product_.data();
}

void MpiFrontTransmittance::send(int block, std::vector<float> transmittance) {
  sent_[block] = true;
  if (behind_[block].empty()) return;
  const std::vector<float>& data = outgoing_.emplace_back(std::move(transmittance));
  for (const int r : behind_[block]) {
    MPI_Request request;
    checkMpi(MPI_Isend(data.data(), planes_size_, MPI_FLOAT, r, block, comm_, &request),
          "MPI_Isend");
    sends_.push_back(request);
  }
  // Lets the transfers move on while this rank renders (MPI progresses inside its calls).
  int flag = 0;
  checkMpi(MPI_Testall(static_cast<int>(sends_.size()), sends_.data(), &flag, MPI_STATUSES_IGNORE),
        "MPI_Testall");
}

void MpiFrontTransmittance::finished(int block, const LightIndependentImage& image) {
  std::vector<float> transmittance;
  if (!behind_[block].empty()) {
    transmittance.resize(planes_size_);
    copyBlockTransmittance(image, block, transmittance.data());
  }
  send(block, std::move(transmittance));
}

void MpiFrontTransmittance::waitForAll() {
  checkMpi(MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE),
        "MPI_Waitall");
  checkMpi(MPI_Waitall(static_cast<int>(sends_.size()), sends_.data(), MPI_STATUSES_IGNORE),
        "MPI_Waitall");
  sends_.clear();
  outgoing_.clear();
  closed_ = true;
}

void MpiFrontTransmittance::done() {
  if (!closed_) waitForAll();
}

void MpiFrontTransmittance::abandon() {
  if (closed_) return;
  for (std::size_t b = 0; b < sent_.size(); ++b)
    if (!sent_[b]) send(static_cast<int>(b), std::vector<float>(planes_size_, 1.f));
  waitForAll();
}

}  // namespace svr
