#pragma once
// Connections wait here, on one poll thread, until the head of their next request has
// arrived; only then do they take an HTTP thread. cpp-httplib gives every connection a
// thread from accept on, so clients that open connections and send their headers slowly
// (or not at all) held every thread and /health went unanswered; here they hold a file
// descriptor and at most `max_head_bytes` of memory each, until:
//  - their head is complete -> `ready` (a worker serves the request);
//  - `head_timeout` has passed since the connection was accepted (or since the first byte
//    of a next request on a kept-alive connection) -> 408, closed;
//  - a kept-alive connection stays idle for `idle_timeout` -> closed;
//  - the head exceeds `max_head_bytes` -> 431, closed;
//  - more than `max_pending` connections wait -> the longest-waiting one is closed. Every
//    loopback client shares one address, so a per-address cap would refuse the page along
//    with the attacker; the oldest-first cap keeps the new, fast clients.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace triax::service {

struct GateLimits {
    std::chrono::milliseconds head_timeout{10000};
    std::chrono::milliseconds idle_timeout{2000};
    std::size_t max_head_bytes = 64 * 1024;
    std::size_t max_pending = 512;
};

// A connection between requests.
struct PendingConnection {
    int fd = -1;
    std::string buffered;    // bytes read, not yet served (the head, maybe more)
    std::size_t served = 0;  // requests already answered on it
};

class HeaderGate {
public:
    using Ready = std::function<void(PendingConnection&&)>;
    HeaderGate(GateLimits limits, Ready ready);
    ~HeaderGate();
    HeaderGate(const HeaderGate&) = delete;
    HeaderGate& operator=(const HeaderGate&) = delete;

    // A freshly accepted connection.
    void admit(int fd);
    // A kept-alive connection after its response; closed if the gate has shut down.
    void resume(PendingConnection&& c);
    // Closes every waiting connection and stops the poll thread.
    void shutdown();

    std::size_t waiting() const;  // connections in the gate now

private:
    struct Entry {
        PendingConnection c;
        std::chrono::steady_clock::time_point since;  // accepted, or the first byte of the next head
        bool idle = false;                            // kept alive, no byte of the next request yet
        std::uint64_t order = 0;                      // admission order (oldest first out)
    };
    void enqueue(Entry e);
    void run();
    // Reads what `e`'s socket has; false when the connection is done with (closed here or handed on).
    bool pump(Entry& e);
    bool overdue(const Entry& e, std::chrono::steady_clock::time_point now) const;
    static bool head_complete(const std::string& b);

    GateLimits limits_;
    Ready ready_;
    mutable std::mutex mutex_;
    std::vector<Entry> incoming_;  // handed in by other threads
    std::size_t waiting_ = 0;
    bool stopping_ = false;
    std::uint64_t next_order_ = 0;
    int wake_[2] = {-1, -1};  // a pipe: writing to it interrupts poll()
    std::thread thread_;
};

// Writes a one-line answer with no body (408, 431) and closes the connection.
void refuse_and_close(int fd, int status, const char* reason);

}  // namespace triax::service
