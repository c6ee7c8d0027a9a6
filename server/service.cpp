#include "server/service.hpp"

#include "server/http/problem.hpp"

#include <chrono>
#include <fstream>
#include <iostream>

namespace triax::service {

using nlohmann::json;

namespace {

std::filesystem::path prepare_data_dir(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw StoreError("cannot create data directory " + dir.string() + ": " + ec.message(), 0);
    return dir / "triax.db";
}

std::optional<json> read_json_file(const std::filesystem::path& p) {
    std::ifstream in(p);
    if (!in) return std::nullopt;
    return json::parse(in);
}

int hardware_threads() {
    const auto n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : static_cast<int>(n);
}

ServiceConfig checked(ServiceConfig c) {
    if (c.workers < 1 || c.workers > 64) throw std::invalid_argument("--workers must be in [1, 64]");
    if (c.queue_limit < 1 || c.queue_limit > 10000) throw std::invalid_argument("--queue-limit must be in [1, 10000]");
    if (c.max_threads_per_run <= 0) c.max_threads_per_run = hardware_threads();
    if (c.threads_per_run < 1 || c.threads_per_run > c.max_threads_per_run)
        throw std::invalid_argument("--threads-per-run must be in [1, " + std::to_string(c.max_threads_per_run) + "]");
    if (c.port < 0 || c.port > 65535) throw std::invalid_argument("--port must be in [0, 65535]");
    return c;
}

}  // namespace

Service::Service(ServiceConfig cfg, RunExecutor executor)
    : config(checked(std::move(cfg))),
      db(prepare_data_dir(config.data_dir), config.schema_dir / "migrations"),
      run_events(db, "run_events", "run_id"),
      diagnosis_events(db, "diagnosis_events", "diagnosis_id"),
      queue(static_cast<std::size_t>(config.workers), static_cast<std::size_t>(config.queue_limit)),
      runs(db, run_events, queue, std::move(executor), config.threads_per_run, config.max_threads_per_run) {
    if (auto s = read_json_file(config.schema_dir / "scheme.schema.json")) scheme_schema.emplace(std::move(*s));
    openapi = read_json_file(config.schema_dir / "openapi.json").value_or(json::object());
    interrupted_at_start = runs.recover_interrupted() + recover_interrupted_diagnoses(*this);
    register_routes();
}

Service::~Service() { stop(); }

void Service::register_routes() {
    const auto threads = static_cast<std::size_t>(config.http_threads);
    http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    http.set_payload_max_length(config.max_body_bytes);
    // A request with neither Content-Length nor Transfer-Encoding has an empty body
    // (RFC 9112 6.3). cpp-httplib 0.11 instead reads such a POST/DELETE until the client
    // closes, i.e. until its read timeout, and answers 400 (`curl -X POST .../cancel`).
    // The pre-routing handler runs before the body is read, so stating the empty length
    // here makes it read nothing. The Request is a non-const local of httplib's connection
    // loop, so writing through the const reference is defined.
    http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
        if (!req.has_header("Content-Length") && !req.has_header("Transfer-Encoding"))
            const_cast<httplib::Request&>(req).headers.emplace("Content-Length", "0");
        return httplib::Server::HandlerResponse::Unhandled;
    });
    http.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
        try {
            std::rethrow_exception(ep);
        } catch (const ApiError& e) {
            send_problem(res, e, req.path);
        } catch (const StoreError& e) {
            const bool full = e.code == SQLITE_FULL;
            send_problem(res,
                         ApiError(full ? 507 : 500, full ? "Insufficient Storage" : "Storage Error",
                                  std::string("the store failed: ") + e.what()),
                         req.path);
        } catch (const std::exception& e) {
            send_problem(res, ApiError(500, "Internal Server Error", e.what()), req.path);
        } catch (...) {
            send_problem(res, ApiError(500, "Internal Server Error", "unknown error"), req.path);
        }
    });
    // Unmatched routes and httplib's own refusals (e.g. 413) become problem details too.
    http.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;
        std::string detail = res.status == 404   ? "no route for " + req.method + " " + req.path
                             : res.status == 413 ? "the request body exceeds the size limit"
                                                 : "request failed";
        ApiError e(res.status, res.status == 404 ? "Not Found" : res.status == 413 ? "Payload Too Large" : "Error", detail);
        send_problem(res, e, req.path);
    });
    register_service_routes(*this);
    register_scheme_routes(*this);
    register_run_routes(*this);
    register_result_routes(*this);
    register_dataset_routes(*this);
    register_comparison_routes(*this);
    register_diagnosis_routes(*this);
}

void Service::route(const std::string& method, const std::string& pattern, httplib::Server::Handler handler) {
    std::string path = pattern;
    for (std::size_t at; (at = path.find("([^/]+)")) != std::string::npos;) path.replace(at, 7, "{id}");
    routes.emplace_back(method, path);
    if (method == "GET") http.Get(pattern, std::move(handler));
    else if (method == "POST") http.Post(pattern, std::move(handler));
    else if (method == "DELETE") http.Delete(pattern, std::move(handler));
    else throw std::logic_error("unsupported method " + method);
}

int Service::bind() {
    bound_port_ = config.port == 0 ? http.bind_to_any_port(config.host) : (http.bind_to_port(config.host, config.port) ? config.port : -1);
    if (bound_port_ < 0) throw std::runtime_error("cannot listen on " + config.host + ":" + std::to_string(config.port));
    return bound_port_;
}

bool Service::listen() { return http.listen_after_bind(); }

int Service::start_background() {
    const int port = bind();
    listener_ = std::thread([this] { listen(); });
    for (int i = 0; i < 5000 && !http.is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return port;
}

std::string Service::url() const { return "http://" + config.host + ":" + std::to_string(bound_port_); }

void Service::stop() {
    if (stopped_) return;
    stopped_ = true;
    shutting_down = true;
    runs.begin_shutdown();
    {
        std::lock_guard lock(diagnosis_mutex);
        for (auto& [id, flag] : diagnosis_cancel) flag->store(true);
    }
    run_events.shutdown();
    diagnosis_events.shutdown();
    http.stop();
    if (listener_.joinable()) listener_.join();
    queue.shutdown();
    // Whatever was still queued or running is recorded as interrupted (re-runnable).
    runs.recover_interrupted();
    recover_interrupted_diagnoses(*this);
}

}  // namespace triax::service
