#pragma once
// Tasks spread over the ranks of an MPI job (Open MPI): rank 0 hands each task to the first
// free rank, one at a time, and collects the results; ranks 1..N-1 serve until rank 0 says
// stop. Rank 0 also runs tasks itself, on one thread of its own beside the dispatching
// threads, so `mpirun -np N` keeps N runs going. Which rank runs a task changes nothing in
// its result (TaskHandler contract), so the results are the same for any N.
//
// Threads: run() may be called from several threads of rank 0 at once (the diagnosis
// evaluates its batches from `concurrency` threads); every MPI call is made under one
// mutex, which needs MPI_THREAD_SERIALIZED (MpiSession asks for it).
//
// Waiting: an idle rank polls (MPI_Iprobe) with a sleep that grows to 20 ms instead of a
// blocking receive, because Open MPI's blocking receive spins on its core, and here the
// waiting ranks share the cores with the ranks that compute.
//
// Failures: a handler that throws gives a TaskResult with ok = false and its message; a
// rank that dies ends the whole job (MPI's default error handler, and mpirun stops every
// rank when one exits abnormally), so a caller never waits for a lost rank.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "server/scaleout/task_runner.hpp"

namespace triax::scaleout {

// MPI_Init_thread / MPI_Finalize for the life of a command. Only for processes started by
// mpirun (launched_by_mpirun()); a plain `triax` never touches MPI.
class MpiSession {
public:
    MpiSession(int& argc, char**& argv);
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }
    // True when this process is one rank of an mpirun (Open MPI or PMIx environment).
    static bool launched_by_mpirun();

private:
    int rank_ = 0, size_ = 1;
};

class MpiTaskPool {
public:
    // Collective: every rank of MPI_COMM_WORLD makes one. `root_computes` = rank 0 runs
    // tasks too (always when it is the only rank).
    explicit MpiTaskPool(bool root_computes = true);
    ~MpiTaskPool();  // rank 0: shutdown()
    MpiTaskPool(const MpiTaskPool&) = delete;
    MpiTaskPool& operator=(const MpiTaskPool&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool is_root() const { return rank_ == 0; }
    // Tasks that run at once: the ranks that compute.
    int width() const { return size_ - (root_computes_ ? 0 : 1); }

    // Collective: true on every rank iff `ok` is true on every rank (e.g. "I could read my
    // inputs"), so no rank starts serving while another has already given up.
    bool all_ok(bool ok) const;

    // Rank 0: runs the tasks; result i belongs to task i. `local` runs the tasks rank 0
    // takes itself. `on_done(i)` (may be empty) is called once per finished task, from the
    // calling thread. Thread-safe.
    std::vector<TaskResult> run(const std::vector<std::string>& tasks, const TaskHandler& local,
                                const std::function<void(std::size_t)>& on_done);
    // Ranks 1..N-1: run the tasks rank 0 sends with `handler` until shutdown.
    void serve(const TaskHandler& handler);
    // Rank 0: waits for tasks in flight, then tells every other rank to stop. Idempotent.
    void shutdown();

private:
    struct Ticket {
        const std::vector<std::string>* tasks = nullptr;
        const TaskHandler* local = nullptr;
        std::vector<TaskResult> results;
        std::vector<std::size_t> finished;  // indices not yet passed to on_done
        std::size_t remaining = 0;
    };
    struct Job {
        Ticket* ticket = nullptr;
        std::size_t index = 0;
    };

    bool pump();  // under mutex_: receives results, hands out tasks; true if anything moved
    void finish(const Job& job, TaskResult result);  // under mutex_
    void local_loop();

    int rank_ = 0, size_ = 1;
    bool root_computes_ = true;
    std::mutex mutex_;
    std::condition_variable done_cv_;   // a task finished
    std::condition_variable local_cv_;  // a task for rank 0's own thread, or stop
    std::deque<Job> pending_;
    std::vector<Job> busy_;             // per rank: the task it runs (ticket null = free)
    std::optional<Job> local_job_;
    std::thread local_thread_;
    bool stopping_ = false;
    bool shut_down_ = false;
};

}  // namespace triax::scaleout
