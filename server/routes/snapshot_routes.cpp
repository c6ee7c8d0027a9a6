// GET /runs/{id}/snapshots, GET /runs/{id}/snapshots/{stage}?format=json|project|spheres|lammps|vtk:
// the specimen at the end of each stage, from the run's stored snapshots (docs/packings.md).
// Eigen before httplib: <resolv.h> (through httplib) defines a macro _res that Eigen uses as a name.
#include "server/io/packing_formats.hpp"
#include "server/http/problem.hpp"
#include "server/service.hpp"

namespace triax::service {

using nlohmann::json;

void register_snapshot_routes(Service& s) {
    s.route("GET", R"(/runs/([^/]+)/snapshots)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        s.runs.status(id);  // 404 for an unknown run
        send_json(res, {{"run_id", id}, {"items", s.runs.snapshots(id)}});
    });
    s.route(
        "GET", R"(/runs/([^/]+)/snapshots/([^/]+))",
        [&s](const httplib::Request& req, httplib::Response& res) {
            const auto id = path_id(req);
            const std::string stage = req.matches[2];
            const std::string name = req.has_param("format") ? req.get_param_value("format") : "json";
            const auto format = io::packing_format_from_name(name);
            if (!format)
                throw bad_request("format must be one of json, project, spheres, lammps, vtk; got '" + name + "'");
            s.runs.status(id);
            const auto bytes = s.runs.snapshot_bytes(id, stage);
            if (!bytes) {
                std::string have;
                for (const auto& it : s.runs.snapshots(id)) have += (have.empty() ? "" : ", ") + it["stage"].get<std::string>();
                throw not_found("run " + std::to_string(id) + " has no snapshot of stage '" + stage + "' (recorded: " +
                                (have.empty() ? std::string("none yet") : have) + ")");
            }
            const auto snap = io::decode_snapshot(*bytes);
            if (*format != io::PackingFormat::Json)
                res.set_header("Content-Disposition", "attachment; filename=\"run-" + std::to_string(id) + "-" + stage +
                                                          io::packing_file_extension(*format) + "\"");
            res.status = 200;
            res.set_content(io::snapshot_to_text(snap, *format), io::packing_content_type(*format));
        },
        "/runs/{id}/snapshots/{stage}");
}

}  // namespace triax::service
