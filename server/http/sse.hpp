#pragma once
// Server-Sent Events over an EventLog: replays everything after Last-Event-ID (header or
// ?last_event_id=) from the store, then follows new events with a timed wait, so a slow or
// vanished client never blocks a run and a stopped server ends the stream. The stream ends
// after the job's terminal event (done/error).
#include "server/events/event_log.hpp"

#include <httplib.h>

#include <atomic>

namespace triax::service {

// Counts open streams against a cap. Every stream holds one HTTP thread for its life, so
// the cap keeps threads free for requests.
class StreamLimiter {
public:
    explicit StreamLimiter(int cap) : cap_(cap) {}
    bool try_acquire() {
        int n = open_.load();
        while (n < cap_)
            if (open_.compare_exchange_weak(n, n + 1)) return true;
        return false;
    }
    void release() { open_.fetch_sub(1); }
    int open() const { return open_.load(); }
    int cap() const { return cap_; }

private:
    const int cap_;
    std::atomic<int> open_{0};
};

// 503 with Retry-After when `limiter` is full; the slot is released when the response
// (and its content provider) is destroyed, whichever way the stream ended. On shutdown the
// stream first sends every stored event (a job interrupted by the stop has its terminal
// event stored before the logs stop), then ends.
void serve_event_stream(const httplib::Request& req, httplib::Response& res, EventLog& log, std::int64_t owner,
                        StreamLimiter& limiter);

// "id: 3\nevent: progress\ndata: {...}\n\n"
std::string format_sse(const StoredEvent& e);

}  // namespace triax::service
