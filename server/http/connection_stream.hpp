#pragma once
// One accepted connection as cpp-httplib's Stream, for a request whose head the
// HeaderGate has already read: the bytes the gate read (head, perhaps part of the body or
// of the next request) come first, then the socket. Reads after the head end at
// `read_deadline` whatever the pace of the client (a body sent a byte every few seconds
// would otherwise hold an HTTP thread for hours under a per-read timeout); each read and
// write also waits at most its own timeout.
#include <httplib.h>

#include <chrono>
#include <string>

namespace triax::service {

class ConnectionStream : public httplib::Stream {
public:
    using Clock = std::chrono::steady_clock;
    ConnectionStream(int fd, std::string buffered, Clock::duration read_timeout, Clock::duration write_timeout,
                     Clock::time_point read_deadline);

    bool is_readable() const override;
    bool is_writable() const override;
    ssize_t read(char* ptr, size_t size) override;
    ssize_t write(const char* ptr, size_t size) override;
    void get_remote_ip_and_port(std::string& ip, int& port) const override;
    void get_local_ip_and_port(std::string& ip, int& port) const override;
    socket_t socket() const override { return fd_; }

    // The bytes read from the socket but not consumed (a pipelined next request).
    std::string take_unread();
    // A read timed out, passed the deadline or found the connection closed: what is left
    // of the request on the socket is unknown, so the connection cannot serve another.
    bool read_failed() const { return read_failed_; }

private:
    int fd_;
    std::string buffer_;
    std::size_t at_ = 0;  // next unread byte of buffer_
    Clock::duration read_timeout_, write_timeout_;
    Clock::time_point read_deadline_;
    bool read_failed_ = false;
};

}  // namespace triax::service
