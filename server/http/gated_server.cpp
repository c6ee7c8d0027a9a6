#include "server/http/gated_server.hpp"

#include "server/http/connection_stream.hpp"

#include <sys/socket.h>
#include <unistd.h>

namespace triax::service {

// httplib's task queue for one listen(): runs the accept loop's task (our
// process_and_close_socket) at once, since it only hands the socket to the gate, and owns
// the gate and the workers; shutdown() (at the end of listen) closes waiting connections
// and joins the workers once their requests are done.
class GatedServer::Dispatcher : public httplib::TaskQueue {
public:
    explicit Dispatcher(GatedServer& server)
        : server_(server),
          workers(server.limits_.threads),
          gate(server.limits_.gate, [this, &server](PendingConnection&& c) {
              auto shared = std::make_shared<PendingConnection>(std::move(c));
              workers.enqueue([&server, shared] { server.serve(std::move(*shared)); });
          }) {}
    ~Dispatcher() override { server_.dispatcher_ = nullptr; }
    void enqueue(std::function<void()> fn) override { fn(); }
    void shutdown() override {
        stopping = true;
        gate.shutdown();
        workers.shutdown();
    }
    GatedServer& server_;
    std::atomic<bool> stopping{false};
    httplib::ThreadPool workers;
    HeaderGate gate;
};

GatedServer::GatedServer(ConnectionLimits limits) : limits_(limits) {
    new_task_queue = [this] {
        auto* d = new Dispatcher(*this);
        dispatcher_ = d;
        return d;
    };
}

std::size_t GatedServer::connections_waiting() const {
    const Dispatcher* d = dispatcher_;
    return d && !d->stopping ? d->gate.waiting() : 0;
}

bool GatedServer::process_and_close_socket(socket_t sock) {
    Dispatcher* d = dispatcher_;
    if (!d || d->stopping) {
        ::close(sock);
        return false;
    }
    d->gate.admit(sock);
    return true;
}

void GatedServer::serve(PendingConnection&& c) {
    Dispatcher* d = dispatcher_;
    using namespace std::chrono;
    const auto read_timeout = seconds(read_timeout_sec_) + microseconds(read_timeout_usec_);
    const auto write_timeout = seconds(write_timeout_sec_) + microseconds(write_timeout_usec_);
    ConnectionStream stream(c.fd, std::move(c.buffered), read_timeout, write_timeout,
                            steady_clock::now() + limits_.body_timeout);
    const bool last = d->stopping || c.served + 1 >= keep_alive_max_count_;
    bool connection_closed = false;
    const bool ok = process_request(stream, last, connection_closed, nullptr);
    if (!ok || connection_closed || last || d->stopping || stream.read_failed()) {
        ::shutdown(c.fd, SHUT_RDWR);
        ::close(c.fd);
        return;
    }
    c.buffered = stream.take_unread();
    ++c.served;
    d->gate.resume(std::move(c));
}

}  // namespace triax::service
