#include "server/jobs/cancel_flags.hpp"

namespace triax::service {

CancelFlags::Flag CancelFlags::arm(std::int64_t id) {
    auto flag = std::make_shared<std::atomic<bool>>(false);
    std::lock_guard lock(mutex_);
    flags_[id] = flag;
    return flag;
}

bool CancelFlags::raise(std::int64_t id) {
    std::lock_guard lock(mutex_);
    const auto it = flags_.find(id);
    if (it == flags_.end()) return false;
    it->second->store(true);
    return true;
}

void CancelFlags::forget(std::int64_t id) {
    std::lock_guard lock(mutex_);
    flags_.erase(id);
}

void CancelFlags::raise_all() {
    std::lock_guard lock(mutex_);
    for (auto& [id, flag] : flags_) flag->store(true);
}

}  // namespace triax::service
