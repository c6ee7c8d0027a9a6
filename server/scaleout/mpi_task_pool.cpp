#include "server/scaleout/mpi_task_pool.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>
#include <thread>
#include <stdexcept>

namespace triax::scaleout {

namespace {

constexpr int kTagTask = 1;      // rank 0 -> worker: task bytes
constexpr int kTagResult = 2;    // worker -> rank 0: '1' + result bytes, or '0' + error message
constexpr int kTagShutdown = 3;  // rank 0 -> worker: no more tasks (empty message)

// Idle polling interval: starts short (a result is picked up within a fraction of a
// millisecond while runs finish), doubles while nothing moves, capped so a waiting rank
// costs next to no CPU and a forward run (seconds to minutes) waits at most 20 ms.
constexpr auto kPollMin = std::chrono::microseconds(100);
constexpr auto kPollMax = std::chrono::microseconds(20000);

std::chrono::microseconds backoff(std::chrono::microseconds d) { return std::min(d * 2, kPollMax); }

std::string received(const MPI_Status& st) {
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    std::string buf(static_cast<std::size_t>(n), '\0');
    MPI_Recv(buf.data(), n, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return buf;
}

void send(const std::string& bytes, int dest, int tag) {
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw std::runtime_error("MPI message of " + std::to_string(bytes.size()) + " bytes exceeds the 2 GiB limit");
    MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD);
}

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        throw std::runtime_error("the MPI library does not support MPI_THREAD_SERIALIZED");
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

bool MpiSession::launched_by_mpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
           std::getenv("PMI_RANK") != nullptr;
}

MpiTaskPool::MpiTaskPool(bool root_computes) {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    root_computes_ = root_computes || size_ == 1;
    busy_.resize(static_cast<std::size_t>(size_));
    if (is_root() && root_computes_) local_thread_ = std::thread([this] { local_loop(); });
}

MpiTaskPool::~MpiTaskPool() {
    if (!is_root()) return;
    try {
        shutdown();
    } catch (...) {
        // MPI errors abort the job (MPI_ERRORS_ARE_FATAL); nothing else can throw here.
    }
}

bool MpiTaskPool::all_ok(bool ok) const {
    int mine = ok ? 1 : 0, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return all == 1;
}

void MpiTaskPool::finish(const Job& job, TaskResult result) {
    job.ticket->results[job.index] = std::move(result);
    job.ticket->finished.push_back(job.index);
    --job.ticket->remaining;
    done_cv_.notify_all();
}

bool MpiTaskPool::pump() {
    bool moved = false;
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, kTagResult, MPI_COMM_WORLD, &flag, &st);
        if (!flag) break;
        std::string msg = received(st);
        const Job job = busy_[static_cast<std::size_t>(st.MPI_SOURCE)];
        busy_[static_cast<std::size_t>(st.MPI_SOURCE)] = Job{};
        TaskResult r;
        r.ok = !msg.empty() && msg[0] == '1';
        r.bytes = msg.empty() ? std::string("empty result message from rank ") + std::to_string(st.MPI_SOURCE) : msg.substr(1);
        if (job.ticket) finish(job, std::move(r));
        moved = true;
    }
    for (int dest = 1; dest < size_ && !pending_.empty(); ++dest) {
        if (busy_[static_cast<std::size_t>(dest)].ticket) continue;
        const Job job = pending_.front();
        pending_.pop_front();
        send((*job.ticket->tasks)[job.index], dest, kTagTask);
        busy_[static_cast<std::size_t>(dest)] = job;
        moved = true;
    }
    if (root_computes_ && !local_job_ && !pending_.empty()) {
        local_job_ = pending_.front();
        pending_.pop_front();
        local_cv_.notify_one();
        moved = true;
    }
    return moved;
}

void MpiTaskPool::local_loop() {
    std::unique_lock lock(mutex_);
    for (;;) {
        local_cv_.wait(lock, [&] { return local_job_.has_value() || stopping_; });
        if (!local_job_) return;
        const Job job = *local_job_;
        lock.unlock();
        TaskResult r = run_task(*job.ticket->local, (*job.ticket->tasks)[job.index]);
        lock.lock();
        local_job_.reset();
        finish(job, std::move(r));
    }
}

std::vector<TaskResult> MpiTaskPool::run(const std::vector<std::string>& tasks, const TaskHandler& local,
                                         const std::function<void(std::size_t)>& on_done) {
    if (!is_root()) throw std::logic_error("MpiTaskPool::run is for rank 0");
    Ticket ticket;
    ticket.tasks = &tasks;
    ticket.local = &local;
    ticket.results.resize(tasks.size());
    ticket.remaining = tasks.size();
    std::unique_lock lock(mutex_);
    if (shut_down_) throw std::logic_error("MpiTaskPool::run after shutdown");
    for (std::size_t i = 0; i < tasks.size(); ++i) pending_.push_back({&ticket, i});
    auto wait = kPollMin;
    for (;;) {
        wait = pump() ? kPollMin : backoff(wait);
        if (!ticket.finished.empty()) {
            std::vector<std::size_t> done;
            done.swap(ticket.finished);
            if (on_done) {
                lock.unlock();
                for (std::size_t i : done) on_done(i);
                lock.lock();
            }
            continue;  // tasks may have finished meanwhile
        }
        if (ticket.remaining == 0) break;
        // Woken early when rank 0's own thread finishes a task; results of other ranks are
        // seen at the next pump.
        done_cv_.wait_for(lock, wait);
    }
    return std::move(ticket.results);
}

void MpiTaskPool::serve(const TaskHandler& handler) {
    if (is_root()) throw std::logic_error("MpiTaskPool::serve is for ranks 1..N-1");
    auto wait = kPollMin;
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag) {
            std::this_thread::sleep_for(wait);
            wait = backoff(wait);
            continue;
        }
        wait = kPollMin;
        const std::string task = received(st);
        if (st.MPI_TAG == kTagShutdown) return;
        TaskResult r = run_task(handler, task);
        send((r.ok ? "1" : "0") + r.bytes, 0, kTagResult);
    }
}

void MpiTaskPool::shutdown() {
    if (!is_root()) return;
    {
        std::unique_lock lock(mutex_);
        if (shut_down_) return;
        shut_down_ = true;
        // Tasks of a run() still going on another thread end as failures (that run returns);
        // the ones in flight are received, so that no worker is left blocked in a send.
        for (const Job& job : pending_) finish(job, {false, "the scale-out pool was shut down before this run started"});
        pending_.clear();
        auto wait = kPollMin;
        while (std::any_of(busy_.begin(), busy_.end(), [](const Job& j) { return j.ticket != nullptr; })) {
            wait = pump() ? kPollMin : backoff(wait);
            done_cv_.wait_for(lock, wait);
        }
        for (int dest = 1; dest < size_; ++dest) send(std::string(), dest, kTagShutdown);
        stopping_ = true;
        local_cv_.notify_all();
    }
    if (local_thread_.joinable()) local_thread_.join();
}

}  // namespace triax::scaleout
