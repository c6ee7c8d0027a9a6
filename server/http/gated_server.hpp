#pragma once
// cpp-httplib's server with its connections taken over after accept: the HeaderGate holds
// each connection until the head of a request has arrived, then one of `threads` workers
// serves that one request (httplib's own process_request) and hands a kept-alive connection
// back to the gate. So a thread is held only while a request is being read (body, bounded
// by body_timeout), handled or answered, never while a client takes its time to send a
// head or sits idle between requests; slow or silent clients cannot starve /health.
// Routes, handlers, limits and timeouts are set on it as on httplib::Server.
#include "server/http/header_gate.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <memory>

namespace triax::service {

struct ConnectionLimits {
    std::size_t threads = 320;                    // workers serving requests (and streams)
    GateLimits gate;
    std::chrono::milliseconds body_timeout{60000};  // a request body must arrive within this (after its head)
};

class GatedServer : public httplib::Server {
public:
    explicit GatedServer(ConnectionLimits limits = {});
    // Before listen: takes effect for the next listen.
    void set_connection_limits(const ConnectionLimits& limits) { limits_ = limits; }
    const ConnectionLimits& connection_limits() const { return limits_; }
    // Connections waiting in the gate for a request head (0 when not listening).
    std::size_t connections_waiting() const;

private:
    class Dispatcher;
    // cpp-httplib calls this for every accepted socket (virtual, on its accept thread with
    // the Dispatcher as task queue): the connection goes to the gate.
    bool process_and_close_socket(socket_t sock) override;
    void serve(PendingConnection&& c);

    ConnectionLimits limits_;
    std::atomic<Dispatcher*> dispatcher_{nullptr};
};

}  // namespace triax::service
