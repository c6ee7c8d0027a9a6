#include "server/jobs/job_queue.hpp"

#include "server/http/problem.hpp"

#include <algorithm>

namespace triax::service {

JobQueue::JobQueue(std::size_t workers, std::size_t limit) : limit_(limit) {
    for (std::size_t i = 0; i < std::max<std::size_t>(workers, 1); ++i) workers_.emplace_back([this] { work(); });
}

JobQueue::~JobQueue() { shutdown(); }

bool JobQueue::try_submit(std::string key, std::function<void()> job) {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ || jobs_.size() >= limit_) return false;
        jobs_.push_back({std::move(key), std::move(job)});
    }
    cv_.notify_one();
    return true;
}

bool JobQueue::withdraw(const std::string& key) {
    std::lock_guard lock(mutex_);
    auto it = std::find_if(jobs_.begin(), jobs_.end(), [&](const Job& j) { return j.key == key; });
    if (it == jobs_.end()) return false;
    jobs_.erase(it);
    return true;
}

std::vector<std::string> JobQueue::shutdown() {
    std::vector<std::string> dropped;
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && workers_.empty()) return dropped;
        stopping_ = true;
        for (auto& j : jobs_) dropped.push_back(j.key);
        jobs_.clear();
    }
    cv_.notify_all();
    for (auto& t : workers_)
        if (t.joinable()) t.join();
    workers_.clear();
    return dropped;
}

std::size_t JobQueue::waiting() const {
    std::lock_guard lock(mutex_);
    return jobs_.size();
}

void JobQueue::work() {
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mutex_);
            cv_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
            if (stopping_) return;
            job = std::move(jobs_.front());
            jobs_.pop_front();
        }
        // Jobs catch their own errors (they record them); this guard keeps a worker alive
        // if one does not.
        try {
            job.fn();
        } catch (...) {
        }
    }
}

ApiError queue_full(const JobQueue& queue, const std::string& detail) {
    return ApiError(429, "Too Many Requests", detail).with_limit("queue_limit = " + std::to_string(queue.limit()));
}

}  // namespace triax::service
