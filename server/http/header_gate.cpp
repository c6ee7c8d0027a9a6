#include "server/http/header_gate.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <string>

namespace triax::service {

using Clock = std::chrono::steady_clock;

namespace {
// How often the poll wakes up to close overdue connections: the timeouts hold to this.
constexpr int kTickMs = 100;
}  // namespace

namespace {
void close_quietly(int fd) {
    ::shutdown(fd, SHUT_RDWR);
    ::close(fd);
}
}  // namespace

void refuse_and_close(int fd, int status, const char* reason) {
    const std::string answer = "HTTP/1.1 " + std::to_string(status) + " " + reason +
                               "\r\nConnection: close\r\nContent-Length: 0\r\n\r\n";
    (void)::send(fd, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    close_quietly(fd);
}

HeaderGate::HeaderGate(GateLimits limits, Ready ready) : limits_(limits), ready_(std::move(ready)) {
    if (::pipe2(wake_, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("cannot create the header gate's pipe");
    thread_ = std::thread([this] { run(); });
}

HeaderGate::~HeaderGate() {
    shutdown();
    ::close(wake_[0]);
    ::close(wake_[1]);
}

void HeaderGate::admit(int fd) { enqueue(Entry{PendingConnection{fd, {}, 0}, Clock::now(), false, 0}); }

void HeaderGate::resume(PendingConnection&& c) { enqueue(Entry{std::move(c), Clock::now(), true, 0}); }

void HeaderGate::enqueue(Entry e) {
    {
        std::lock_guard lock(mutex_);
        if (!stopping_) {
            e.order = next_order_++;
            incoming_.push_back(std::move(e));
            e.c.fd = -1;
        }
    }
    if (e.c.fd >= 0) close_quietly(e.c.fd);  // the gate has shut down
    const char byte = 1;
    (void)::write(wake_[1], &byte, 1);
}

void HeaderGate::shutdown() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        stopping_ = true;
    }
    const char byte = 1;
    (void)::write(wake_[1], &byte, 1);
    if (thread_.joinable()) thread_.join();
}

std::size_t HeaderGate::waiting() const {
    std::lock_guard lock(mutex_);
    return waiting_;
}

bool HeaderGate::head_complete(const std::string& b) { return b.find("\r\n\r\n") != std::string::npos; }

bool HeaderGate::overdue(const Entry& e, Clock::time_point now) const {
    return now - e.since > (e.idle ? limits_.idle_timeout : limits_.head_timeout);
}

bool HeaderGate::pump(Entry& e) {
    char buf[16 * 1024];
    const ssize_t n = ::recv(e.c.fd, buf, sizeof buf, MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return true;
    if (n <= 0) {  // closed by the client, or broken
        close_quietly(e.c.fd);
        return false;
    }
    if (e.idle) {  // the next request has begun: its head has head_timeout from now
        e.idle = false;
        e.since = Clock::now();
    }
    e.c.buffered.append(buf, static_cast<std::size_t>(n));
    if (head_complete(e.c.buffered)) {
        ready_(std::move(e.c));
        return false;
    }
    if (e.c.buffered.size() > limits_.max_head_bytes) {
        refuse_and_close(e.c.fd, 431, "Request Header Fields Too Large");
        return false;
    }
    return true;
}

void HeaderGate::run() {
    std::vector<Entry> entries;
    std::vector<pollfd> fds;
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) break;
            for (auto& e : incoming_) entries.push_back(std::move(e));
            incoming_.clear();
        }
        // A kept-alive connection may bring its next head with the last response's bytes.
        entries.erase(std::remove_if(entries.begin(), entries.end(),
                                     [&](Entry& e) {
                                         if (!head_complete(e.c.buffered)) return false;
                                         ready_(std::move(e.c));
                                         return true;
                                     }),
                      entries.end());
        const auto now = Clock::now();
        entries.erase(std::remove_if(entries.begin(), entries.end(),
                                     [&](Entry& e) {
                                         if (!overdue(e, now)) return false;
                                         if (e.c.buffered.empty()) close_quietly(e.c.fd);
                                         else refuse_and_close(e.c.fd, 408, "Request Timeout");
                                         return true;
                                     }),
                      entries.end());
        if (entries.size() > limits_.max_pending) {
            std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.order < b.order; });
            const auto excess = static_cast<std::ptrdiff_t>(entries.size() - limits_.max_pending);
            for (auto it = entries.begin(); it != entries.begin() + excess; ++it) close_quietly(it->c.fd);
            entries.erase(entries.begin(), entries.begin() + excess);
        }
        {
            std::lock_guard lock(mutex_);
            waiting_ = entries.size();
        }
        fds.assign(1, pollfd{wake_[0], POLLIN, 0});
        for (const auto& e : entries) fds.push_back(pollfd{e.c.fd, POLLIN, 0});
        if (::poll(fds.data(), fds.size(), kTickMs) < 0 && errno != EINTR) break;
        if (fds[0].revents & POLLIN) {
            char drain[256];
            while (::read(wake_[0], drain, sizeof drain) > 0) {
            }
        }
        // fds[k + 1] belongs to entries[k]: entries do not change between building and here.
        std::vector<Entry> kept;
        kept.reserve(entries.size());
        for (std::size_t k = 0; k < entries.size(); ++k) {
            if (fds[k + 1].revents == 0 || pump(entries[k])) kept.push_back(std::move(entries[k]));
        }
        entries.swap(kept);
    }
    for (auto& e : entries) close_quietly(e.c.fd);
    std::lock_guard lock(mutex_);
    for (auto& e : incoming_) close_quietly(e.c.fd);
    incoming_.clear();
    waiting_ = 0;
}

}  // namespace triax::service
