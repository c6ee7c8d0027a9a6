#pragma once
// Server-Sent Events over an EventLog: replays everything after Last-Event-ID (header or
// ?last_event_id=) from the store, then follows new events with a timed wait, so a slow or
// vanished client never blocks a run and a stopped server ends the stream. The stream ends
// after the job's terminal event (done/error).
#include "server/events/event_log.hpp"

#include <httplib.h>

namespace triax::service {

void serve_event_stream(const httplib::Request& req, httplib::Response& res, EventLog& log, std::int64_t owner);

// "id: 3\nevent: progress\ndata: {...}\n\n"
std::string format_sse(const StoredEvent& e);

}  // namespace triax::service
