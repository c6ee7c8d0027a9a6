#include "server/http/sse.hpp"

#include "server/http/problem.hpp"

#include <charconv>
#include <chrono>

namespace triax::service {

std::string format_sse(const StoredEvent& e) {
    // data is single-line JSON (dump() escapes newlines), so one data: line suffices.
    return "id: " + std::to_string(e.seq) + "\nevent: " + e.type + "\ndata: " + e.data + "\n\n";
}

void serve_event_stream(const httplib::Request& req, httplib::Response& res, EventLog& log, std::int64_t owner,
                        StreamLimiter& limiter) {
    std::int64_t last = 0;
    std::string from = req.get_header_value("Last-Event-ID");
    if (from.empty() && req.has_param("last_event_id")) from = req.get_param_value("last_event_id");
    if (!from.empty()) {
        auto [p, ec] = std::from_chars(from.data(), from.data() + from.size(), last);
        if (ec != std::errc() || p != from.data() + from.size() || last < 0)
            throw bad_request("Last-Event-ID must be a non-negative integer, got '" + from + "'");
    }
    if (!limiter.try_acquire()) {
        res.set_header("Retry-After", "5");
        throw ApiError(503, "Service Unavailable",
                       "too many open event streams (" + std::to_string(limiter.cap()) +
                           "); close one or poll the status route")
            .with_limit("event streams <= " + std::to_string(limiter.cap()));
    }
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    auto quiet_since = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
    res.set_chunked_content_provider(
        "text/event-stream", [&log, owner, last, quiet_since](size_t, httplib::DataSink& sink) mutable {
            const bool stopping = log.stopping();
            const auto events = log.since(owner, last, 256);
            for (const auto& e : events) {
                const auto text = format_sse(e);
                if (!sink.write(text.data(), text.size())) return false;
                last = e.seq;
                if (is_terminal_event(e.type)) {
                    sink.done();
                    return true;
                }
            }
            if (!events.empty()) {
                *quiet_since = std::chrono::steady_clock::now();
                return true;
            }
            if (stopping) {
                sink.done();
                return true;
            }
            // A client reconnecting after the terminal event (EventSource does so by
            // itself) gets an empty, closed stream instead of an endless wait.
            if (log.ended(owner)) {
                sink.done();
                return true;
            }
            log.wait(owner, last, std::chrono::milliseconds(500));
            if (!sink.is_writable()) return false;
            // A comment line every 15 s keeps proxies from closing an idle stream.
            if (std::chrono::steady_clock::now() - *quiet_since > std::chrono::seconds(15)) {
                static const std::string ping = ": keep-alive\n\n";
                if (!sink.write(ping.data(), ping.size())) return false;
                *quiet_since = std::chrono::steady_clock::now();
            }
            return true;
        },
        [&limiter](bool) { limiter.release(); });
}

}  // namespace triax::service
