#pragma once
// The parsed result documents of the last few finished runs. A run's result document
// (summary + every series) is written once, when the run ends, and never changes; every GET
// of one of its series would otherwise read and parse the whole document again (the load
// test's result routes spent most of their time there). Thread-safe; least recently used
// out first.
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <utility>

#include <nlohmann/json.hpp>

namespace triax::service {

class ResultCache {
public:
    using Document = std::shared_ptr<const nlohmann::json>;

    explicit ResultCache(std::size_t capacity) : capacity_(capacity) {}

    // The cached document of run `id`, or nullptr.
    Document find(std::int64_t id) {
        std::lock_guard lock(mutex_);
        for (auto it = entries_.begin(); it != entries_.end(); ++it)
            if (it->first == id) {
                entries_.splice(entries_.begin(), entries_, it);
                return entries_.front().second;
            }
        return nullptr;
    }

    void put(std::int64_t id, Document doc) {
        std::lock_guard lock(mutex_);
        entries_.remove_if([id](const auto& e) { return e.first == id; });
        entries_.emplace_front(id, std::move(doc));
        while (entries_.size() > capacity_) entries_.pop_back();
    }

private:
    std::mutex mutex_;
    std::size_t capacity_;
    std::list<std::pair<std::int64_t, Document>> entries_;
};

}  // namespace triax::service
