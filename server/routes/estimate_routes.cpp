// POST /estimate: what a scheme will cost before it is submitted (particles, steps, minutes
// as a range, warnings). The scheme passes the same checks as POST /schemes (a scheme the
// service would refuse gets the same 422 naming the field) and is not stored. Body: the
// scheme, or {"scheme": {...}} as POST /runs takes it.
#include "engine/protocol/run_estimate.hpp"
#include "server/http/problem.hpp"
#include "server/service.hpp"

namespace triax::service {

using nlohmann::json;

void register_estimate_routes(Service& s) {
    s.route("POST", "/estimate", [&s](const httplib::Request& req, httplib::Response& res) {
        const json body = parse_body(req);
        const bool wrapped = body.is_object() && body.contains("scheme") && body["scheme"].is_object();
        const auto scheme = validated_scheme(s, wrapped ? body["scheme"] : body, wrapped ? "/scheme" : "");
        protocol::RunEstimate e;
        try {
            e = protocol::estimate_run(scheme);
        } catch (const std::exception& ex) {
            throw unprocessable(ex.what()).at_field(wrapped ? "/scheme" : "");
        }
        const auto steps = [](const protocol::PhaseSteps& p) {
            return json{{"low", p.low}, {"typical", p.typical}, {"high", p.high}};
        };
        send_json(res, {{"grains", e.size.grains},
                        {"membrane_particles", e.size.membrane_particles},
                        {"contacts_estimate", e.size.contacts_estimate},
                        {"memory_MB", e.size.memory_bytes / 1.0e6},
                        {"grain_mean_diameter_mm", 2.0e3 * e.grain_mean_radius_m},
                        {"grain_max_diameter_mm", 2.0e3 * e.grain_max_radius_m},
                        {"membrane_particle_radius_mm", 1.0e3 * e.membrane_radius_m},
                        {"time_step_s", e.time_step_s},
                        {"steps", e.total.typical},
                        {"steps_by_phase", {{"consolidation", steps(e.consolidation)}, {"shear", steps(e.shear)},
                                            {"creep", steps(e.creep)}, {"total", steps(e.total)}}},
                        {"creep_increments", e.creep_increments},
                        {"minutes_estimate", {{"low", e.minutes_low}, {"typical", e.minutes_typical}, {"high", e.minutes_high},
                                              {"cap", e.minutes_cap}}},
                        {"warnings", e.warnings}});
    });
}

}  // namespace triax::service
