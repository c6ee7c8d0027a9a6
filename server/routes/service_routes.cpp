// GET /health, /openapi.json, /presets, /schema/scheme, /vendor/{file} (the page's npm
// packages), and the web page (/, /static/...).
#include "server/http/problem.hpp"
#include "server/io/scheme_json.hpp"
#include "server/service.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string_view>

namespace triax::service {

namespace {

struct VendorFile {
    const char* name;      // as requested under /vendor/
    const char* path;      // under web/node_modules/
    const char* mime;
};

// The only files of web/node_modules the page loads (web/package.json installs them).
// A whitelist, not a mount: node_modules holds much more than the page needs.
constexpr VendorFile kVendorFiles[] = {
    {"uPlot.esm.js", "uplot/dist/uPlot.esm.js", "text/javascript"},
    {"uPlot.min.css", "uplot/dist/uPlot.min.css", "text/css"},
    {"three.module.js", "three/build/three.module.js", "text/javascript"},
    {"three.core.js", "three/build/three.core.js", "text/javascript"},
    {"OrbitControls.js", "three/examples/jsm/controls/OrbitControls.js", "text/javascript"},
};

}  // namespace

bool is_private_web_path(const std::string& path) {
    // One spelling per resource: the prefix checks below would miss "/static/./package.json"
    // or "//node_modules/...", which the file handler resolves to the same file. No route and
    // no file is named with an empty segment ("//") or a dot segment ("." or "..").
    if (path.find("//") != std::string::npos) return true;
    for (std::size_t at = 0; at < path.size();) {
        const auto end = std::min(path.find('/', at + 1), path.size());
        const std::string_view segment = std::string_view(path).substr(at + 1, end - at - 1);
        if (segment == "." || segment == "..") return true;
        at = end;
    }
    // The npm install tree and its manifests are served only through /vendor/.
    for (std::string_view hidden : {"/node_modules", "/package.json", "/package-lock.json"}) {
        for (std::string_view prefix : {"", "/static"}) {
            const std::string p = std::string(prefix) + std::string(hidden);
            if (path.compare(0, p.size(), p) == 0) return true;
        }
    }
    return false;
}

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
    s.route("GET", R"(/vendor/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        const std::string name = req.matches[1];
        for (const auto& f : kVendorFiles) {
            if (name != f.name) continue;
            const auto file = s.config.web_dir / "node_modules" / f.path;
            std::ifstream in(file, std::ios::binary);
            if (!in)
                throw not_found("vendor file " + name + " is not installed (" + file.string() +
                                "); run scripts/install-deps.sh (npm install in web/)");
            std::ostringstream body;
            body << in.rdbuf();
            res.status = 200;
            res.set_header("Cache-Control", "max-age=3600");
            res.set_content(body.str(), f.mime);
            return;
        }
        throw not_found("no vendor file named " + name);
    });
    // Static files take precedence over GET routes in cpp-httplib; the web directory holds
    // no file named like an API path, and is_private_web_path hides its npm tree.
    s.http.set_mount_point("/static", s.config.web_dir.string());
    s.http.set_mount_point("/", s.config.web_dir.string());
}

}  // namespace triax::service
