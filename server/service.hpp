#pragma once
// triaxd as an object: configuration, the SQLite store, event logs, the job queue, the run
// service and the HTTP server with every route. main.cpp only parses flags and calls
// start(); the end-to-end tests start it in-process on an ephemeral port.
#include "engine/diagnose/lab_data.hpp"
#include "server/diagnoses/diagnosis_service.hpp"
#include "server/ensembles/ensemble_service.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "server/events/event_log.hpp"
#include "server/http/gated_server.hpp"
#include "server/http/request_guard.hpp"
#include "server/http/sse.hpp"
#include "server/io/json_schema_validator.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/runs/run_executor.hpp"
#include "server/runs/run_service.hpp"
#include "server/scaleout/mpi_job_launcher.hpp"
#include "server/store/comparison_store.hpp"
#include "server/store/database.hpp"
#include "server/store/dataset_store.hpp"
#include "server/store/packing_store.hpp"
#include "server/store/scheme_store.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <regex>
#include <vector>

namespace triax::protocol {
struct ImportedPacking;
}

namespace triax::service {

struct ServiceConfig {
    std::string host = "127.0.0.1";
    int port = 8080;                       // 0 = any free port (tests)
    std::filesystem::path data_dir = "data";
    std::filesystem::path web_dir = std::filesystem::path(TRIAX_SOURCE_DIR) / "web";
    std::filesystem::path schema_dir = std::filesystem::path(TRIAX_SOURCE_DIR) / "schema";
    int workers = 1;
    int threads_per_run = 1;               // default OpenMP threads of a run
    int max_threads_per_run = 0;           // 0 = the machine's hardware threads
    int queue_limit = 16;                  // waiting runs (plus diagnoses) before 429
    std::size_t max_body_bytes = 16u << 20;  // uploads and schemes, chunked or not (413 beyond)
    int max_particles = 200000;            // estimated soil particles of a scheme
    // Every open connection holds one HTTP thread (cpp-httplib's model), an SSE stream for
    // its whole life. Streams are capped below the pool so that requests (and /health)
    // always find a thread: at most max_event_streams streams (503 beyond), and the pool
    // has http_threads >= max_event_streams + 32.
    int http_threads = 320;
    int max_event_streams = 256;
    int listen_backlog = 512;              // pending connections the kernel queues (>= 128)
    // A connection holds no HTTP thread until the head of a request has arrived
    // (server/http/gated_server.hpp): it waits in the gate at most head_timeout (408), at
    // most max_waiting_connections wait (the longest-waiting is closed beyond), and a
    // request body must arrive within body_timeout of its head.
    std::chrono::milliseconds head_timeout{10000};
    std::chrono::milliseconds body_timeout{60000};
    int max_waiting_connections = 512;
    std::string token;                     // --token / TRIAX_TOKEN: required on every route but /health
    std::vector<std::string> allowed_hosts;  // extra Host names accepted (--allow-host)
    // Diagnoses as MPI jobs (mpirun --hostfile H -np N triax diagnose ...) when ranks > 0.
    scaleout::MpiLaunchSettings mpi;
};

class Service {
public:
    // Opens the store (applying migrations), marks runs left running as interrupted and
    // registers the routes. Does not listen yet.
    Service(ServiceConfig config, RunExecutor executor);
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // Binds host:port (port 0 = ephemeral) and returns the bound port.
    int bind();
    // Serves until stop(); returns false if the server failed.
    bool listen();
    // bind() + listen() on a background thread; returns the port.
    int start_background();
    // Interrupts running jobs (recorded "interrupted", re-runnable), lets open streams
    // deliver their terminal event, then stops accepting and joins everything. Safe to
    // call from a signal-waiting thread while another thread is in listen().
    void stop();

    std::string url() const;

    // Used by the route files.
    ServiceConfig config;
    Database db;
    // The tables the routes read and write, one store each (no SQL in the routes).
    SchemeStore schemes{db};
    DatasetStore datasets{db};
    PackingStore packings{db};
    ComparisonStore comparisons{db};
    EventLog run_events;
    EventLog diagnosis_events;
    JobQueue queue;
    RunService runs;
    DiagnosisService diagnoses;
    EnsembleService ensembles;
    std::optional<io::JsonSchemaValidator> scheme_schema;  // absent if schema/scheme.schema.json is missing
    nlohmann::json openapi;
    GatedServer http;
    int interrupted_at_start = 0;

    // Registers a handler and records (method, OpenAPI path) so a test can check the
    // routes against schema/openapi.json; "([^/]+)" in the pattern is "{id}" there.
    // `described`: the OpenAPI path when a capture is not an {id} (e.g. "/runs/{id}/snapshots/{stage}").
    void route(const std::string& method, const std::string& pattern, httplib::Server::Handler handler,
               const std::string& described = "");
    std::vector<std::pair<std::string, std::string>> routes;
    // Open SSE streams, capped at config.max_event_streams (503 beyond).
    StreamLimiter event_streams;

    std::atomic<bool> shutting_down{false};  // set by stop()

private:
    void register_routes();
    // Methods registered for a path ("GET, POST"), empty if no route matches it.
    std::string allowed_methods(const std::string& path) const;
    std::vector<std::pair<std::string, std::regex>> route_patterns_;
    RequestGuard guard_;
    int listen_socket_ = -1;
    int bound_port_ = 0;
    std::thread listener_;
    std::mutex stop_mutex_;
    bool stopped_ = false;
};

// Route groups, one file each.
void register_service_routes(Service& s);
// Paths that are not served: any with an empty or dot segment ("//", "/./", "/../"), and
// the web directory's npm tree (the page's packages are served through the /vendor/
// whitelist).
bool is_private_web_path(const std::string& path);
void register_scheme_routes(Service& s);
void register_run_routes(Service& s);
void register_result_routes(Service& s);
void register_dataset_routes(Service& s);
void register_comparison_routes(Service& s);
void register_envelope_routes(Service& s);
void register_diagnosis_routes(Service& s);
// Start-up: fills datasets.header_json for rows stored without it; returns how many.
int backfill_dataset_headers(Service& s);
void register_estimate_routes(Service& s);
void register_snapshot_routes(Service& s);
void register_packing_routes(Service& s);
void register_ensemble_routes(Service& s);

// Shared helper of scheme and run routes: validates a scheme document (JSON Schema, then
// the engine's own checks and the service limits) and stores it; returns {"id","scheme"}.
nlohmann::json store_scheme(Service& s, const nlohmann::json& scheme, const std::string& pointer_prefix);
// The same checks without storing: the parsed scheme (POST /estimate).
protocol::TestScheme validated_scheme(Service& s, const nlohmann::json& scheme, const std::string& pointer_prefix);
// A stored dataset (404 if unknown); `name` receives its name when not null.
diagnose::LabDataset load_dataset(Service& s, std::int64_t id, std::string* name);
// A stored packing (404 naming /packing_id if unknown).
protocol::ImportedPacking load_packing(Service& s, std::int64_t id);

}  // namespace triax::service
