#pragma once
// Working memory a renderer keeps from one frame for the next: large per-frame arrays (shear-warp's
// intermediate image, the splats' projections, sort keys and lists) allocated afresh each frame
// cost their first touch, a page fault per 4 KiB — here about as much as writing the page, tens
// of milliseconds a frame. One object per render running at a time on the renderer.

#include <memory>
#include <mutex>
#include <vector>

namespace svr {

template <class T>
class ReusePool {
 public:
  // An object a finished frame left (its arrays at their last sizes), or a new one; back in the
  // pool when the lease ends.
  class Lease {
   public:
    Lease(ReusePool& pool, std::unique_ptr<T> object) : pool_(pool), object_(std::move(object)) {}
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() {
      const std::lock_guard lock(pool_.mutex_);
      pool_.free_.push_back(std::move(object_));
    }
    T& operator*() const { return *object_; }
    T* operator->() const { return object_.get(); }

   private:
    ReusePool& pool_;
    std::unique_ptr<T> object_;
  };

  Lease take() {
    {
      const std::lock_guard lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<T> object = std::move(free_.back());
        free_.pop_back();
        return Lease(*this, std::move(object));
      }
    }
    return Lease(*this, std::make_unique<T>());
  }

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace svr
