#pragma once
// A 500 is the service's fault: the client learns only that it happened and under which
// request id; the operator finds the id, the request line and the exception's own text in
// stderr. The exception text (a parser's message, a file path, an SQL error) never goes to
// the client.
#include "server/http/problem.hpp"

#include <httplib.h>

#include <string>

namespace triax::service {

// A fresh request id: 16 hex digits, unique enough to find one line in a log.
std::string new_request_id();

// Writes "triaxd: 500 request <id>: METHOD PATH: <what>" to stderr and returns the problem
// to send: status 500, the id in `request_id` and in the detail, nothing of `what`.
ApiError internal_error(const httplib::Request& req, const std::string& what);

}  // namespace triax::service
