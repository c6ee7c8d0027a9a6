#pragma once
// A task of the scale-out layer: bytes in, bytes out, the same on every rank and thread.
// MpiTaskPool runs tasks on MPI ranks; run_tasks_in_threads is the same contract in this
// process (for `triax` started without mpirun). Result i belongs to task i and depends only
// on it.
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace triax::scaleout {

// A handler's answer: the result bytes, or (ok = false) the message of what it threw.
struct TaskResult {
    bool ok = false;
    std::string bytes;
};

// Runs one task. Must be callable from several threads at once; throws on failure.
using TaskHandler = std::function<std::string(std::string_view task)>;

inline TaskResult run_task(const TaskHandler& handler, std::string_view task) {
    TaskResult r;
    try {
        r.bytes = handler(task);
        r.ok = true;
    } catch (const std::exception& e) {
        r.bytes = e.what();
    } catch (...) {
        r.bytes = "unknown exception";
    }
    return r;
}

// `on_done(i)` (may be empty) is called once per finished task, from any of the threads.
inline std::vector<TaskResult> run_tasks_in_threads(const std::vector<std::string>& tasks, const TaskHandler& handler,
                                                    int threads, const std::function<void(std::size_t)>& on_done) {
    std::vector<TaskResult> out(tasks.size());
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < tasks.size();) {
            out[i] = run_task(handler, tasks[i]);
            if (on_done) on_done(i);
        }
    };
    const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), tasks.size());
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    return out;
}

}  // namespace triax::scaleout
