#pragma once
// Data a backend derives from one classification and reuses on every frame (the splat list of
// non-empty voxels, GL buffers): built on first use, under a lock so that two renders of the
// same classification on two threads build it once, and dropped with the classification. A
// classification is never modified after classify(), so nothing cached here goes stale.

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace svr {

class DerivedCache {
 public:
  template <class T>
  std::shared_ptr<const T> get(const std::string& key,
                               const std::function<std::shared_ptr<const T>()>& build) {
    const std::lock_guard lock(mutex_);
    auto& slot = items_[key];
    if (!slot) slot = build();
    return std::static_pointer_cast<const T>(slot);
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const void>> items_;
};

}  // namespace svr
