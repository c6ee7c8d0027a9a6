// POST /packings (a sphere list or the project JSON as the body), GET /packings/{id}: grains
// made elsewhere that a run starts from (POST /runs with packing_id; docs/packings.md).
// Eigen before httplib: <resolv.h> (through httplib) defines a macro _res that Eigen uses as a name.
#include "server/io/packing_formats.hpp"
#include "server/http/problem.hpp"
#include "server/service.hpp"

namespace triax::service {

using nlohmann::json;

protocol::ImportedPacking load_packing(Service& s, std::int64_t id) {
    return io::packing_from_project_json(s.packings.packing(id, "/packing_id"), "packing " + std::to_string(id));
}

void register_packing_routes(Service& s) {
    s.route("POST", "/packings", [&s](const httplib::Request& req, httplib::Response& res) {
        if (req.body.empty()) throw bad_request("the request body is empty; upload the sphere list or project JSON as the body");
        std::optional<std::string> units;
        if (req.has_param("units")) units = req.get_param_value("units");
        const std::string name = req.has_param("name") ? req.get_param_value("name") : "packing";
        check_resource_name(name, "query parameter 'name'");
        protocol::ImportedPacking p;
        try {
            p = io::parse_packing(req.body, "upload", units);
        } catch (const io::PackingParseError& e) {
            auto err = unprocessable(e.what());
            if (e.line > 0) err.at(e.line, 1);
            if (!e.pointer.empty()) err.at_field(e.pointer);
            throw err;
        }
        if (p.size() > static_cast<std::size_t>(s.config.max_particles))
            throw unprocessable("the packing has " + std::to_string(p.size()) + " grains; this service accepts at most " +
                                std::to_string(s.config.max_particles))
                .with_limit("grains <= " + std::to_string(s.config.max_particles));
        const std::string format = req.body.find_first_not_of(" \t\r\n") != std::string::npos &&
                                           req.body[req.body.find_first_not_of(" \t\r\n")] == '{'
                                       ? "project"
                                       : "spheres";
        const auto created = utc_now();
        const auto id =
            s.packings.insert(name, format, static_cast<std::int64_t>(p.size()), io::packing_to_project_json(p), created);
        res.set_header("Location", "/packings/" + std::to_string(id));
        send_json(res, {{"id", id}, {"name", name}, {"format", format}, {"grains", p.size()}, {"created_at", created}}, 201);
    });
    s.route("GET", R"(/packings/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.packings.get(path_id(req)));
    });
}

}  // namespace triax::service
