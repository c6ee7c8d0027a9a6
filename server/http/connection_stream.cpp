#include "server/http/connection_stream.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace triax::service {

namespace {

using Clock = ConnectionStream::Clock;

// Waits until `fd` is ready for `events` or `wait` has passed; true when ready.
bool wait_for(int fd, short events, Clock::duration wait) {
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(wait).count();
    if (ms <= 0) return false;
    pollfd p{fd, events, 0};
    int rc;
    do rc = ::poll(&p, 1, static_cast<int>(ms));
    while (rc < 0 && errno == EINTR);
    return rc > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
}

void address_of(const sockaddr_storage& addr, socklen_t len, std::string& ip, int& port) {
    char host[NI_MAXHOST], serv[NI_MAXSERV];
    if (getnameinfo(reinterpret_cast<const sockaddr*>(&addr), len, host, sizeof host, serv, sizeof serv,
                    NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
        ip = host;
        port = std::atoi(serv);
    }
}

}  // namespace

ConnectionStream::ConnectionStream(int fd, std::string buffered, Clock::duration read_timeout,
                                   Clock::duration write_timeout, Clock::time_point read_deadline)
    : fd_(fd), buffer_(std::move(buffered)), read_timeout_(read_timeout), write_timeout_(write_timeout),
      read_deadline_(read_deadline) {}

bool ConnectionStream::is_readable() const {
    if (at_ < buffer_.size()) return true;
    return wait_for(fd_, POLLIN, std::min(read_timeout_, read_deadline_ - Clock::now()));
}

bool ConnectionStream::is_writable() const {
    if (!wait_for(fd_, POLLOUT, write_timeout_)) return false;
    // Writable but closed by the peer (an SSE client went away): a peek reads 0.
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 0) <= 0) return true;
    char byte;
    return ::recv(fd_, &byte, 1, MSG_PEEK | MSG_DONTWAIT) > 0;
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
    if (at_ >= buffer_.size()) {
        if (!is_readable()) {
            read_failed_ = true;
            return -1;
        }
        buffer_.resize(16 * 1024);
        at_ = 0;
        ssize_t n;
        do n = ::recv(fd_, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
        while (n < 0 && errno == EINTR);
        buffer_.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
        if (n <= 0) {
            read_failed_ = true;
            return n;
        }
    }
    const std::size_t n = std::min(size, buffer_.size() - at_);
    std::memcpy(ptr, buffer_.data() + at_, n);
    at_ += n;
    return static_cast<ssize_t>(n);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
    if (!wait_for(fd_, POLLOUT, write_timeout_)) return -1;
    ssize_t n;
    do n = ::send(fd_, ptr, size, MSG_NOSIGNAL);  // SO_SNDTIMEO (set at accept) bounds a partial wait
    while (n < 0 && errno == EINTR);
    return n;
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    if (getpeername(fd_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) address_of(addr, len, ip, port);
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    if (getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) address_of(addr, len, ip, port);
}

std::string ConnectionStream::take_unread() {
    std::string rest = buffer_.substr(std::min(at_, buffer_.size()));
    buffer_.clear();
    at_ = 0;
    return rest;
}

}  // namespace triax::service
