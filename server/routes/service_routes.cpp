// GET /health, /openapi.json, /presets, /schema/scheme, and the web page (/, /static/...).
#include "server/http/problem.hpp"
#include "server/io/scheme_json.hpp"
#include "server/service.hpp"

namespace triax::service {

void register_service_routes(Service& s) {
    s.route("GET", "/health", [&s](const httplib::Request&, httplib::Response& res) {
        send_json(res, {{"status", "ok"},
                        {"version", s.openapi.contains("info") ? s.openapi["info"].value("version", "0.1.0") : "0.1.0"},
                        {"schema_version", s.db.schema_version()},
                        {"workers", s.queue.workers()},
                        {"queue_waiting", s.queue.waiting()},
                        {"queue_limit", s.queue.limit()}});
    });
    s.route("GET", "/openapi.json", [&s](const httplib::Request&, httplib::Response& res) {
        if (s.openapi.empty()) throw not_found("schema/openapi.json was not found at start-up");
        send_json(res, s.openapi);
    });
    s.route("GET", "/presets", [](const httplib::Request&, httplib::Response& res) { send_json(res, io::presets_to_json()); });
    s.route("GET", "/schema/scheme", [&s](const httplib::Request&, httplib::Response& res) {
        if (!s.scheme_schema) throw not_found("schema/scheme.schema.json was not found at start-up");
        res.status = 200;
        res.set_content(s.scheme_schema->schema().dump(), "application/schema+json");
    });
    // Static files take precedence over GET routes in cpp-httplib; the web directory holds
    // no file named like an API path.
    s.http.set_mount_point("/static", s.config.web_dir.string());
    s.http.set_mount_point("/", s.config.web_dir.string());
}

}  // namespace triax::service
