#include "harness/mpi/mpi_distribution.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "harness/mpi/mpi_check.h"
#include "harness/mpi/mpi_front_transmittance.h"
#include "renderers/render/brick_order.h"
#include "renderers/render/image_compositing.h"

namespace svr {
namespace {

// The layout of the samples the depth-ordered reduce combines. MPI's user operations take no
// argument of ours, and the reduce runs on the calling thread, so its layout is set here for
// the length of one call.
struct ReduceLayout {
  int k = 0, t_channels = 0;
};
thread_local ReduceLayout reduce_layout;

// MPI applies a non-commutative operation as inout := in ∘ inout with `in` from the lower rank:
// in depth order, the image in front.
void overOperation(void* in, void* inout, int* len, MPI_Datatype*) {
  compositeOverInterleaved(static_cast<const float*>(in), static_cast<float*>(inout),
                           static_cast<std::size_t>(*len), reduce_layout.k,
                           reduce_layout.t_channels);
}

bool powerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

}  // namespace

MpiDistribution::MpiDistribution(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

void MpiDistribution::balance(const WorkGrid* on_writer) {
  int cells[4] = {0, 0, 0, 0};  // whether there is an estimate, then its cells
  if (rank_ == 0 && on_writer)
    cells[0] = 1, std::copy(on_writer->cells.begin(), on_writer->cells.end(), cells + 1);
  checkMpi(MPI_Bcast(cells, 4, MPI_INT, 0, comm_), "MPI_Bcast");
  work_.reset();
  if (!cells[0]) return;
  WorkGrid work{{cells[1], cells[2], cells[3]}, {}};
  work.cost = rank_ == 0 ? on_writer->cost
                         : std::vector<float>(static_cast<std::size_t>(cells[1]) * cells[2] * cells[3]);
  checkMpi(MPI_Bcast(work.cost.data(), static_cast<int>(work.cost.size()), MPI_FLOAT, 0, comm_),
        "MPI_Bcast");
  work_ = std::move(work);
}

VolumeBrick MpiDistribution::brick(const Dims& whole) {
  whole_ = whole;
  bricks_ = kdSplit(whole, size_, work_ ? &*work_ : nullptr);
  return brickOf(whole, bricks_[rank_].own);
}

std::pair<double, double> MpiDistribution::wholeRange(std::pair<double, double> local) {
  double lo = local.first, hi = local.second;
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, comm_), "MPI_Allreduce");
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, comm_), "MPI_Allreduce");
  return {lo, hi};
}

FieldRange MpiDistribution::wholeField(const FieldRange& local) {
  FieldRange out = local;
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, &out.lo, 1, MPI_FLOAT, MPI_MIN, comm_), "MPI_Allreduce");
  float hi[2] = {local.hi, local.largest};
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, hi, 2, MPI_FLOAT, MPI_MAX, comm_), "MPI_Allreduce");
  out.hi = hi[0], out.largest = hi[1];
  return out;
}

const char* MpiDistribution::compositing() const {
  return powerOfTwo(size_) ? "binary swap" : "reduce";
}

std::vector<std::pair<std::size_t, std::size_t>> MpiDistribution::swapRegions(
    std::size_t pixels) const {
  std::vector<std::pair<std::size_t, std::size_t>> regions(size_, {0, pixels});
  for (int bit = 1; bit < size_; bit <<= 1)
    for (int d = 0; d < size_; ++d) {
      auto& [begin, end] = regions[d];
      const std::size_t mid = begin + (end - begin) / 2;
      if (d & bit)
        begin = mid;
      else
        end = mid;
    }
  return regions;
}

std::vector<float> MpiDistribution::binarySwap(MPI_Comm depth, int position,
                                               std::vector<float> samples, int stride, int k,
                                               int t_channels) const {
  const std::size_t pixels = samples.size() / stride;
  std::size_t begin = 0, end = pixels;
  std::vector<float> received;
  for (int bit = 1; bit < size_; bit <<= 1) {
    // Partners differ in this bit of their depth position; the lower one is in front and keeps
    // the first half of what both hold.
    const int partner = position ^ bit;
    const bool front = (position & bit) == 0;
    const std::size_t mid = begin + (end - begin) / 2;
    const std::size_t keep_begin = front ? begin : mid, keep_end = front ? mid : end;
    const std::size_t send_begin = front ? mid : begin, send_end = front ? end : mid;
    received.resize((keep_end - keep_begin) * stride);
    checkMpi(MPI_Sendrecv(samples.data() + send_begin * stride,
                       static_cast<int>((send_end - send_begin) * stride), MPI_FLOAT, partner, bit,
                       received.data(), static_cast<int>(received.size()), MPI_FLOAT, partner, bit,
                       depth, MPI_STATUS_IGNORE),
          "MPI_Sendrecv");
    float* mine = samples.data() + keep_begin * stride;
    const std::size_t n = keep_end - keep_begin;
    if (front) {
      // mine over theirs, kept in mine: composite into the received copy, then move it back.
      compositeOverInterleaved(mine, received.data(), n, k, t_channels);
      std::copy(received.begin(), received.end(), mine);
    } else {
      compositeOverInterleaved(received.data(), mine, n, k, t_channels);
    }
    begin = keep_begin, end = keep_end;
  }
  // Rank 0 of the world gathers every position's piece, in pixel order.
  int root = 0;
  {
    const int is_root = rank_ == 0 ? position : 0;
    checkMpi(MPI_Allreduce(&is_root, &root, 1, MPI_INT, MPI_MAX, depth), "MPI_Allreduce");
  }
  const auto regions = swapRegions(pixels);
  std::vector<int> counts(size_), displacements(size_);
  for (int d = 0; d < size_; ++d) {
    counts[d] = static_cast<int>((regions[d].second - regions[d].first) * stride);
    displacements[d] = static_cast<int>(regions[d].first * stride);
  }
  std::vector<float> whole(rank_ == 0 ? samples.size() : 0);
  checkMpi(MPI_Gatherv(samples.data() + begin * stride, static_cast<int>((end - begin) * stride),
                    MPI_FLOAT, whole.data(), counts.data(), displacements.data(), MPI_FLOAT, root,
                    depth),
        "MPI_Gatherv");
  return whole;
}

std::vector<float> MpiDistribution::reduceInDepthOrder(MPI_Comm depth, std::vector<float> samples,
                                                       int stride, int k,
                                                       int t_channels) const {
  MPI_Datatype pixel;
  checkMpi(MPI_Type_contiguous(stride, MPI_FLOAT, &pixel), "MPI_Type_contiguous");
  MPI_Type_commit(&pixel);
  MPI_Op over;
  checkMpi(MPI_Op_create(&overOperation, /*commute=*/0, &over), "MPI_Op_create");
  reduce_layout = {k, t_channels};
  // The result lands on depth position 0, then goes to world rank 0 if that is another rank.
  std::vector<float> result(samples.size());
  const int code = MPI_Reduce(samples.data(), result.data(),
                              static_cast<int>(samples.size() / stride), pixel, over, 0, depth);
  MPI_Op_free(&over);
  MPI_Type_free(&pixel);
  checkMpi(code, "MPI_Reduce");
  int position = 0;
  MPI_Comm_rank(depth, &position);
  int front_rank = position == 0 ? rank_ : 0;
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, &front_rank, 1, MPI_INT, MPI_MAX, comm_), "MPI_Allreduce");
  if (front_rank != 0) {
    if (position == 0)
      checkMpi(MPI_Send(result.data(), static_cast<int>(result.size()), MPI_FLOAT, 0, 1, comm_),
            "MPI_Send");
    else if (rank_ == 0)
      checkMpi(MPI_Recv(result.data(), static_cast<int>(result.size()), MPI_FLOAT, front_rank, 1,
                     comm_, MPI_STATUS_IGNORE),
            "MPI_Recv");
  }
  if (rank_ != 0) result.clear();
  return result;
}

std::unique_ptr<FrontTransmittance> MpiDistribution::frontTransmittance(
    const Camera& camera, int width, int height, int t_channels, const glm::dvec3& spacing) {
  if (size_ == 1) return nullptr;
  return std::make_unique<MpiFrontTransmittance>(
      comm_, bricks_, visibilityOrder(bricks_, camera, whole_, spacing), whole_, spacing, camera,
      width, height, t_channels);
}

LightIndependentImage MpiDistribution::composite(const LightIndependentImage& local,
                                                 const Camera& camera,
                                                 const glm::dvec3& spacing) {
  const int k = local.channels(), kt = local.transmittanceChannels();
  const int stride = k + kt;
  if (size_ == 1) return local;
  // Ranks renumbered front to back for this view.
  const std::vector<int> order = visibilityOrder(bricks_, camera, whole_, spacing);
  const int position =
      static_cast<int>(std::find(order.begin(), order.end(), rank_) - order.begin());
  MPI_Comm depth;
  checkMpi(MPI_Comm_split(comm_, 0, position, &depth), "MPI_Comm_split");
  std::vector<float> samples = interleavedSamples(local);
  std::vector<float> whole = powerOfTwo(size_)
                                 ? binarySwap(depth, position, std::move(samples), stride, k, kt)
                                 : reduceInDepthOrder(depth, std::move(samples), stride, k, kt);
  MPI_Comm_free(&depth);
  if (rank_ != 0) return {};
  return fromInterleaved(whole, local.width(), local.height(), k, kt);
}

nlohmann::json MpiDistribution::gather(const nlohmann::json& local) {
  const std::string text = local.dump();
  const int length = static_cast<int>(text.size());
  std::vector<int> lengths(size_), displacements(size_);
  checkMpi(MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, comm_), "MPI_Gather");
  int total = 0;
  for (int r = 0; r < size_; ++r) displacements[r] = total, total += lengths[r];
  std::string all(rank_ == 0 ? total : 0, '\0');
  checkMpi(MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(),
                    displacements.data(), MPI_CHAR, 0, comm_),
        "MPI_Gatherv");
  nlohmann::json out = nlohmann::json::array();
  if (rank_ == 0)
    for (int r = 0; r < size_; ++r) {
      nlohmann::json entry = nlohmann::json::parse(all.substr(displacements[r], lengths[r]));
      entry["rank"] = r;
      out.push_back(std::move(entry));
    }
  return out;
}

void MpiDistribution::agree(const std::exception_ptr& failure) {
  std::string message;
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::bad_alloc&) {
      message = "out of memory";
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
      message = "unknown failure";
    }
  }
  int first = failure ? rank_ : size_;
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm_), "MPI_Allreduce");
  if (first == size_) return;
  int length = static_cast<int>(message.size());
  checkMpi(MPI_Bcast(&length, 1, MPI_INT, first, comm_), "MPI_Bcast");
  message.resize(length);
  checkMpi(MPI_Bcast(message.data(), length, MPI_CHAR, first, comm_), "MPI_Bcast");
  throw AgreedFailure(fmt::format("rank {} of {}: {}", first, size_, message));
}

}  // namespace svr
