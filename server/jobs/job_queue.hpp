#pragma once
// Bounded FIFO of jobs served by a fixed pool of worker threads. HTTP handlers only
// enqueue (never wait for a job); a full queue is refused so the caller can answer 429.
// A job still waiting can be withdrawn; a running job is stopped cooperatively by its
// owner (the run's cancel flag), not by this queue.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace triax::service {

struct ApiError;  // server/http/problem.hpp

class JobQueue {
public:
    JobQueue(std::size_t workers, std::size_t limit);
    ~JobQueue();
    JobQueue(const JobQueue&) = delete;
    JobQueue& operator=(const JobQueue&) = delete;

    // key identifies the job for withdraw() (e.g. "run:7"). False when the queue is full
    // or shutting down.
    bool try_submit(std::string key, std::function<void()> job);
    // Removes a job that has not started. True if it was still waiting.
    bool withdraw(const std::string& key);
    // Stops taking jobs, drops the waiting ones (returned keys), joins the workers after
    // their current job.
    std::vector<std::string> shutdown();

    std::size_t waiting() const;
    std::size_t limit() const { return limit_; }
    std::size_t workers() const { return workers_.size(); }

private:
    void work();
    struct Job {
        std::string key;
        std::function<void()> fn;
    };
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Job> jobs_;
    std::vector<std::thread> workers_;
    std::size_t limit_;
    bool stopping_ = false;
};

// The 429 a service answers when try_submit() refuses its job: `detail` for the client,
// the queue's limit as the limit exceeded.
ApiError queue_full(const JobQueue& queue, const std::string& detail = "the job queue is full; retry later");

}  // namespace triax::service
