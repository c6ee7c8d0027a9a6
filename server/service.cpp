#include "server/service.hpp"

#include "server/io/lab_format.hpp"
#include "server/scaleout/mpi_job_launcher.hpp"

#include "server/http/internal_error.hpp"
#include "server/http/problem.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <chrono>
#include <fstream>
#include <set>
#include <iostream>

namespace triax::service {

using nlohmann::json;

namespace {

// POST/DELETE bodies are read through the ContentReader with a cap: cpp-httplib applies
// its payload limit to a Content-Length but reads a chunked body whole. Past the cap the
// rest is read and dropped (up to kDrainBytes, so that the client can read the 413
// instead of a reset), then the connection is abandoned.
constexpr std::size_t kDrainBytes = 64u << 20;

httplib::Server::HandlerWithContentReader read_capped(std::size_t cap, httplib::Server::Handler handler) {
    return [cap, handler = std::move(handler)](const httplib::Request& req, httplib::Response& res,
                                                const httplib::ContentReader& reader) {
        std::string body;
        std::size_t seen = 0;
        if (req.is_multipart_form_data()) {
            // Form uploads are not taken (the file or document is the body itself), and
            // cpp-httplib cannot hand a multipart body to a plain reader: read and drop it,
            // so that the client reads the 415.
            reader([](const httplib::MultipartFormData&) { return true; },
                   [&](const char*, std::size_t n) { return (seen += n) <= cap + kDrainBytes; });
            throw ApiError(415, "Unsupported Media Type",
                           "multipart/form-data is not accepted: send the document itself as the body, "
                           "Content-Type application/json for JSON endpoints, the file as text (text/csv, "
                           "text/plain) for POST /datasets and POST /packings");
        }
        const bool complete = reader([&](const char* data, std::size_t n) {
            seen += n;
            if (seen <= cap) body.append(data, n);
            else body.clear();
            return seen <= cap + kDrainBytes;
        });
        const bool declared_over = req.has_header("Content-Length") &&
                                   std::strtoull(req.get_header_value("Content-Length").c_str(), nullptr, 10) > cap;
        if (seen > cap || declared_over)
            throw ApiError(413, "Payload Too Large",
                           "the request body exceeds the size limit of " + std::to_string(cap) + " bytes")
                .with_limit("body bytes <= " + std::to_string(cap));
        if (!complete) throw bad_request("the request body could not be read completely");
        // The Request is a non-const local of httplib's connection loop (as in the
        // pre-routing handler): the handlers read the body from it as usual.
        const_cast<httplib::Request&>(req).body = std::move(body);
        handler(req, res);
    };
}

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
    if (c.max_event_streams < 1) throw std::invalid_argument("--max-streams must be >= 1");
    if (c.http_threads < c.max_event_streams + 8)
        throw std::invalid_argument("--http-threads must exceed --max-streams by at least 8 (requests need threads)");
    if (c.listen_backlog < 128) throw std::invalid_argument("--backlog must be >= 128");
    if (c.head_timeout < std::chrono::milliseconds(100) || c.head_timeout > std::chrono::minutes(10))
        throw std::invalid_argument("--head-timeout must be in [0.1, 600] s");
    if (c.max_waiting_connections < 16) throw std::invalid_argument("--max-waiting must be >= 16");
    for (char ch : c.token)
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.' && ch != '~')
            throw std::invalid_argument("--token may hold only letters, digits and - _ . ~");
    if (!c.token.empty() && c.token.size() < 16) throw std::invalid_argument("--token must be at least 16 characters");
    return c;
}

}  // namespace

Service::Service(ServiceConfig cfg, RunExecutor executor)
    : config(checked(std::move(cfg))),
      db(prepare_data_dir(config.data_dir), config.schema_dir / "migrations"),
      run_events(db, "run_events", "run_id"),
      diagnosis_events(db, "diagnosis_events", "diagnosis_id"),
      queue(static_cast<std::size_t>(config.workers), static_cast<std::size_t>(config.queue_limit)),
      runs(db, run_events, queue, std::move(executor), config.threads_per_run, config.max_threads_per_run),
      diagnoses(db, diagnosis_events, queue, [this](std::int64_t id) { return load_dataset(*this, id, nullptr); }),
      ensembles(db, queue, config.threads_per_run, config.max_threads_per_run),
      event_streams(config.max_event_streams),
      guard_(GuardConfig{config.host, config.port, config.allowed_hosts, config.token}) {
    if (auto s = read_json_file(config.schema_dir / "scheme.schema.json")) scheme_schema.emplace(std::move(*s));
    openapi = read_json_file(config.schema_dir / "openapi.json").value_or(json::object());
    interrupted_at_start = runs.recover_interrupted() + diagnoses.recover_interrupted() + ensembles.recover_interrupted();
    backfill_dataset_headers(*this);
    // With --mpi-ranks a diagnosis runs as an mpirun job of the triax CLI (server/scaleout).
    if (config.mpi.enabled())
        diagnoses.set_remote_runner([this](std::int64_t id, const json& request, const diagnose::LabDataset& lab,
                                           diagnose::DiagnoseObserver& observer) {
            return scaleout::run_diagnosis_over_mpi(config.mpi, config.data_dir / "diagnoses" / std::to_string(id),
                                                    {request["scheme"], io::lab_dataset_to_json(lab), request["options"]},
                                                    observer);
        });
    register_routes();
}

Service::~Service() { stop(); }

void Service::register_routes() {
    ConnectionLimits limits;
    limits.threads = static_cast<std::size_t>(config.http_threads);
    limits.gate.head_timeout = config.head_timeout;
    // An idle kept-alive connection waits in the gate (a descriptor, no thread) this long.
    limits.gate.idle_timeout = std::chrono::seconds(2);
    limits.gate.max_pending = static_cast<std::size_t>(config.max_waiting_connections);
    limits.body_timeout = config.body_timeout;
    http.set_connection_limits(limits);
    http.set_payload_max_length(config.max_body_bytes);
    // Each read of a body and each write of an answer waits at most this long.
    http.set_read_timeout(10, 0);
    // cpp-httplib listens with a backlog of 5 (compiled into Debian's library): keep the
    // listening socket to listen() on it again with ours after the bind (Service::bind).
    http.set_socket_options([this](socket_t sock) {
        httplib::default_socket_options(sock);
        listen_socket_ = sock;
    });
    // A request with neither Content-Length nor Transfer-Encoding has an empty body
    // (RFC 9112 6.3). cpp-httplib 0.11 instead reads such a POST/DELETE until the client
    // closes, i.e. until its read timeout, and answers 400 (`curl -X POST .../cancel`).
    // The pre-routing handler runs before the body is read, so stating the empty length
    // here makes it read nothing. The Request is a non-const local of httplib's connection
    // loop, so writing through the const reference is defined.
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        if (!req.has_header("Content-Length") && !req.has_header("Transfer-Encoding"))
            const_cast<httplib::Request&>(req).headers.emplace("Content-Length", "0");
        // A decoded path with a NUL or control byte ("/static/index.html%00.png") names no
        // file: the file system would stop at the NUL and the extension would lie.
        if (std::any_of(req.path.begin(), req.path.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; })) {
            send_problem(res, not_found("no resource at a path with control characters"), "");
            return httplib::Server::HandlerResponse::Handled;
        }
        // Static files are looked up before the routes: the web directory's npm tree is
        // hidden here (the page gets its packages from /vendor/).
        if (is_private_web_path(req.path)) {
            send_problem(res, not_found("no route for " + req.method + " " + req.path), req.path);
            return httplib::Server::HandlerResponse::Handled;
        }
        if (auto refusal = guard_.check(req)) {
            send_problem(res, ApiError(refusal->status, refusal->title, refusal->detail), req.path);
            if (refusal->status == 401) res.set_header("WWW-Authenticate", "Bearer");
            return httplib::Server::HandlerResponse::Handled;
        }
        if (const auto cookie = guard_.token_cookie(req); !cookie.empty()) res.set_header("Set-Cookie", cookie);
        return httplib::Server::HandlerResponse::Unhandled;
    });
    http.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
        try {
            std::rethrow_exception(ep);
        } catch (const ApiError& e) {
            send_problem(res, e, req.path);
        } catch (const NotFound& e) {
            auto problem = not_found(e.what());
            if (!e.field.empty()) problem.at_field(e.field);
            send_problem(res, problem, req.path);
        } catch (const StoreError& e) {
            if (e.code == SQLITE_FULL)
                send_problem(res, ApiError(507, "Insufficient Storage", "the disk holding the store is full"), req.path);
            else
                send_problem(res, internal_error(req, std::string("store: ") + e.what()), req.path);
        } catch (const std::exception& e) {
            send_problem(res, internal_error(req, e.what()), req.path);
        } catch (...) {
            send_problem(res, internal_error(req, "an exception that is not a std::exception"), req.path);
        }
    });
    // Unmatched routes and httplib's own refusals (e.g. 413) become problem details too; a
    // path served under other methods is 405 with Allow.
    http.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;
        if (res.status == 404) {
            if (const auto allow = allowed_methods(req.path); !allow.empty()) {
                res.set_header("Allow", allow);
                send_problem(res, ApiError(405, "Method Not Allowed", req.method + " is not allowed on " + req.path +
                                                                          " (allowed: " + allow + ")"),
                             req.path);
                return;
            }
        }
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
    register_envelope_routes(*this);
    register_diagnosis_routes(*this);
    register_estimate_routes(*this);
    register_snapshot_routes(*this);
    register_packing_routes(*this);
    register_ensemble_routes(*this);
    // Last: bodies sent to no route (or with PUT/PATCH) are read under the same cap, then
    // answered 405 (the path has other methods) or 404; cpp-httplib would otherwise read a
    // chunked body whole before finding no handler.
    const auto refuse = [this](const httplib::Request& req, httplib::Response& res) {
        const auto allow = allowed_methods(req.path);
        if (allow.empty()) throw not_found("no route for " + req.method + " " + req.path);
        res.set_header("Allow", allow);
        throw ApiError(405, "Method Not Allowed", req.method + " is not allowed on " + req.path + " (allowed: " + allow + ")");
    };
    http.Post(".*", read_capped(config.max_body_bytes, refuse));
    http.Delete(".*", read_capped(config.max_body_bytes, refuse));
    http.Put(".*", read_capped(config.max_body_bytes, refuse));
    http.Patch(".*", read_capped(config.max_body_bytes, refuse));
}

void Service::route(const std::string& method, const std::string& pattern, httplib::Server::Handler handler,
                    const std::string& described) {
    std::string path = pattern;
    for (std::size_t at; (at = path.find("([^/]+)")) != std::string::npos;) path.replace(at, 7, "{id}");
    if (!described.empty()) path = described;
    routes.emplace_back(method, path);
    route_patterns_.emplace_back(method, std::regex(pattern));
    if (method == "GET") http.Get(pattern, std::move(handler));
    else if (method == "POST") http.Post(pattern, read_capped(config.max_body_bytes, std::move(handler)));
    else if (method == "DELETE") http.Delete(pattern, read_capped(config.max_body_bytes, std::move(handler)));
    else throw std::logic_error("unsupported method " + method);
}

std::string Service::allowed_methods(const std::string& path) const {
    std::set<std::string> found;
    for (const auto& [method, re] : route_patterns_)
        if (std::regex_match(path, re)) found.insert(method);
    std::string out;
    for (const char* m : {"GET", "HEAD", "POST", "DELETE"}) {
        const bool has = found.count(m) || (std::string(m) == "HEAD" && found.count("GET"));
        if (has) out += (out.empty() ? "" : ", ") + std::string(m);
    }
    return out;
}

int Service::bind() {
    bound_port_ = config.port == 0 ? http.bind_to_any_port(config.host) : (http.bind_to_port(config.host, config.port) ? config.port : -1);
    if (bound_port_ < 0) throw std::runtime_error("cannot listen on " + config.host + ":" + std::to_string(config.port));
    // listen() again on the bound socket sets the backlog (Linux: listen(2) on a listening
    // socket updates it).
    if (listen_socket_ < 0 || ::listen(listen_socket_, config.listen_backlog) != 0)
        throw std::runtime_error("cannot set the listen backlog on " + config.host + ":" + std::to_string(bound_port_));
    guard_.set_port(bound_port_);
    return bound_port_;
}

bool Service::listen() { return shutting_down ? true : http.listen_after_bind(); }

int Service::start_background() {
    const int port = bind();
    listener_ = std::thread([this] { listen(); });
    for (int i = 0; i < 5000 && !http.is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return port;
}

std::string Service::url() const { return "http://" + config.host + ":" + std::to_string(bound_port_); }

void Service::stop() {
    std::lock_guard stop_lock(stop_mutex_);
    if (stopped_) return;
    stopped_ = true;
    shutting_down = true;
    runs.begin_shutdown();
    diagnoses.begin_shutdown();
    ensembles.begin_shutdown();
    // Jobs first: each running job stops at its next cancel poll and is recorded
    // "interrupted" with its terminal event; queued ones are recorded after the join.
    queue.shutdown();
    runs.recover_interrupted();
    diagnoses.recover_interrupted();
    ensembles.recover_interrupted();
    // The streams deliver what is stored (the terminal events) and end; then the server.
    run_events.shutdown();
    diagnosis_events.shutdown();
    // cpp-httplib ends a chunked stream mid-way once the server stops: give the streams up
    // to 2 s to send what is stored and close (each releases its slot when it has).
    for (int i = 0; i < 200 && event_streams.open() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    http.stop();
    if (listener_.joinable()) listener_.join();
}

}  // namespace triax::service
