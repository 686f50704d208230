#pragma once
// An observer as a disk-cache key (base/disk_cache.h): its grid and weighted colour-matching
// functions, which is everything a trained model or designed palette depends on from it.

#include <nlohmann/json.hpp>

namespace svr {

class Observer;

nlohmann::json observerKey(const Observer& observer);

}  // namespace svr
