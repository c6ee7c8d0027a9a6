#include "server/http/internal_error.hpp"

#include <cstdio>
#include <random>

namespace triax::service {

std::string new_request_id() {
    thread_local std::mt19937_64 rng(std::random_device{}());
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(rng()));
    return text;
}

ApiError internal_error(const httplib::Request& req, const std::string& what) {
    const std::string id = new_request_id();
    // One fprintf: lines of concurrent requests do not interleave.
    std::fprintf(stderr, "triaxd: 500 request %s: %s %s: %s\n", id.c_str(), req.method.c_str(), req.path.c_str(),
                 what.c_str());
    std::fflush(stderr);
    ApiError e(500, "Internal Server Error", "the service failed on this request (logged as request " + id + ")");
    e.request_id = id;
    return e;
}

}  // namespace triax::service
