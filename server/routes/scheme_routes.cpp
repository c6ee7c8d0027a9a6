// POST /schemes, GET /schemes, GET /schemes/{id}. A scheme is checked three ways before it
// is stored: the JSON Schema (field pointers for types, ranges, unknown fields), the
// engine's own TestScheme::validate through scheme_from_json, and the service's size limit
// on the estimated particle count (so nobody queues a 1e9-particle run).
#include "engine/protocol/gradation.hpp"
#include "server/http/paging.hpp"
#include "server/http/problem.hpp"
#include "server/io/scheme_json.hpp"
#include "server/service.hpp"

#include <cmath>

namespace triax::service {

using nlohmann::json;

namespace {

// Expected number of soil particles: solid volume over the mean particle volume of each
// size class (radii uniform by number within a class: E[r^3] = (b^4 - a^4) / (4 (b - a))).
double estimated_particle_count(const protocol::TestScheme& sc) {
    const double pi = 3.14159265358979323846;
    const double v_total = pi * 0.25 * sc.specimen.diameter_m * sc.specimen.diameter_m * sc.specimen.height_m;
    const double v_solid = v_total * (1.0 - sc.specimen.target_porosity);
    double n = 0.0;
    for (const auto& c : protocol::size_classes(sc.gradation)) {
        const double a = c.r_lo_m, b = std::max(c.r_hi_m, c.r_lo_m);
        const double r3 = b > a ? (std::pow(b, 4) - std::pow(a, 4)) / (4.0 * (b - a)) : a * a * a;
        if (r3 > 0) n += c.mass_fraction * v_solid / (4.0 / 3.0 * pi * r3);
    }
    return n;
}

}  // namespace

protocol::TestScheme validated_scheme(Service& s, const json& scheme, const std::string& prefix) {
    if (!scheme.is_object()) throw unprocessable("a scheme must be a JSON object").at_field(prefix.empty() ? "" : prefix);
    if (s.scheme_schema) {
        const auto errors = s.scheme_schema->validate(scheme);
        if (!errors.empty()) {
            std::string detail = errors.front().message;
            if (errors.size() > 1) detail += " (and " + std::to_string(errors.size() - 1) + " more)";
            auto e = unprocessable(detail).at_field(prefix + errors.front().pointer);
            throw e;
        }
    }
    protocol::TestScheme parsed;
    try {
        parsed = io::scheme_from_json(scheme);
    } catch (const io::SchemeError& e) {
        throw unprocessable(e.what()).at_field(prefix + e.field);
    } catch (const std::exception& e) {
        throw unprocessable(e.what()).at_field(prefix.empty() ? "" : prefix);
    }
    double estimate = 0.0;
    try {
        estimate = estimated_particle_count(parsed);
    } catch (const std::exception& e) {
        throw unprocessable(e.what()).at_field(prefix + "/gradation");
    }
    const double effective = parsed.max_particles > 0 ? std::min<double>(estimate, parsed.max_particles) : estimate;
    if (!(effective <= s.config.max_particles))
        throw unprocessable("the scheme would generate about " + std::to_string(static_cast<long long>(effective)) +
                            " particles; this service accepts at most " + std::to_string(s.config.max_particles) +
                            " (set max_particles or a coarser gradation)")
            .at_field(prefix + "/max_particles")
            .with_limit("particle_count <= " + std::to_string(s.config.max_particles));
    return parsed;
}

json store_scheme(Service& s, const json& scheme, const std::string& prefix) {
    const protocol::TestScheme parsed = validated_scheme(s, scheme, prefix);
    const json normalised = io::scheme_to_json(parsed);
    const std::string name = normalised.value("name", std::string("custom"));
    const auto id = s.schemes.insert(name, normalised);
    return {{"id", id}, {"name", name}, {"scheme", normalised}};
}

void register_scheme_routes(Service& s) {
    s.route("POST", "/schemes", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, store_scheme(s, parse_body(req), ""), 201);
    });
    s.route("GET", "/schemes", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.schemes.page(page_request(req)));
    });
    s.route("GET", R"(/schemes/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        auto out = s.schemes.get(path_id(req));
        out["scheme"] = io::without_retired_fields(std::move(out["scheme"]));
        send_json(res, out);
    });
}

}  // namespace triax::service
