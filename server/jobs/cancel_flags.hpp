#pragma once
// The cancel flags of one service's jobs, by job id. A job's flag is shared with the worker
// that runs it, which polls it and stops cooperatively; the service raises it on a cancel
// request or at shutdown. Armed when the job is submitted, forgotten when it finishes or
// its submission is refused, so raise_all() reaches only jobs that may still run.
// Thread-safe: handlers, workers and the shutdown path call it concurrently.
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>

namespace triax::service {

class CancelFlags {
public:
    using Flag = std::shared_ptr<std::atomic<bool>>;

    // A fresh lowered flag for job `id` (replacing any earlier one), to hand to its worker.
    Flag arm(std::int64_t id);
    // Raises the flag of job `id`. False if none is armed (the job has finished).
    bool raise(std::int64_t id);
    void forget(std::int64_t id);
    void raise_all();

private:
    std::mutex mutex_;
    std::map<std::int64_t, Flag> flags_;
};

}  // namespace triax::service
