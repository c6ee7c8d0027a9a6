#pragma once
// triaxd as an object: configuration, the SQLite store, event logs, the job queue, the run
// service and the HTTP server with every route. main.cpp only parses flags and calls
// start(); the end-to-end tests start it in-process on an ephemeral port.
#include "engine/diagnose/lab_data.hpp"
#include "server/events/event_log.hpp"
#include "server/io/json_schema_validator.hpp"
#include "server/jobs/job_queue.hpp"
#include "server/runs/run_executor.hpp"
#include "server/runs/run_service.hpp"
#include "server/store/database.hpp"

#include <httplib.h>

#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <memory>
#include <optional>
#include <string>
#include <thread>

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
    std::size_t max_body_bytes = 16u << 20;  // uploads and schemes
    int max_particles = 200000;            // estimated soil particles of a scheme
    int http_threads = 32;                 // SSE clients each hold one
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
    // Stops accepting, ends streams, interrupts running jobs, joins everything.
    void stop();

    std::string url() const;

    // Used by the route files.
    ServiceConfig config;
    Database db;
    EventLog run_events;
    EventLog diagnosis_events;
    JobQueue queue;
    RunService runs;
    std::optional<io::JsonSchemaValidator> scheme_schema;  // absent if schema/scheme.schema.json is missing
    nlohmann::json openapi;
    httplib::Server http;
    int interrupted_at_start = 0;

    // Registers a handler and records (method, OpenAPI path) so a test can check the
    // routes against schema/openapi.json; "([^/]+)" in the pattern is "{id}" there.
    void route(const std::string& method, const std::string& pattern, httplib::Server::Handler handler);
    std::vector<std::pair<std::string, std::string>> routes;

    // Diagnosis jobs (diagnosis_routes.cpp): cancel flags shared with the workers.
    std::atomic<bool> shutting_down{false};  // set by stop(): cancelled jobs become "interrupted"
    std::mutex diagnosis_mutex;
    std::map<std::int64_t, std::shared_ptr<std::atomic<bool>>> diagnosis_cancel;

private:
    void register_routes();
    int bound_port_ = 0;
    std::thread listener_;
    bool stopped_ = false;
};

// Route groups, one file each.
void register_service_routes(Service& s);
void register_scheme_routes(Service& s);
void register_run_routes(Service& s);
void register_result_routes(Service& s);
void register_dataset_routes(Service& s);
void register_comparison_routes(Service& s);
void register_diagnosis_routes(Service& s);
int recover_interrupted_diagnoses(Service& s);

// Shared helper of scheme and run routes: validates a scheme document (JSON Schema, then
// the engine's own checks and the service limits) and stores it; returns {"id","scheme"}.
nlohmann::json store_scheme(Service& s, const nlohmann::json& scheme, const std::string& pointer_prefix);
// A stored dataset (404 if unknown); `name` receives its name when not null.
diagnose::LabDataset load_dataset(Service& s, std::int64_t id, std::string* name);

}  // namespace triax::service
