// GET /datasets/{id}/envelope and GET /runs/{id}/envelope: the Mohr circles at failure
// and the Mohr-Coulomb fit (c' kPa, phi' deg) of a dataset's shear curves or of a finished
// run's shear curve, both through io::strength_envelope_json (the engine's lab_macro fit).
// A run has one sigma3: its envelope is the line through the origin tangent to its circle.
#include "server/http/problem.hpp"
#include "server/io/strength_envelope_json.hpp"
#include "server/service.hpp"

namespace triax::service {

using nlohmann::json;

namespace {

// The run's shear curve as a lab curve (SI): q and eps_a from its stress_strain series
// (columns axial_strain_pct, q_kPa, ...), sigma3 from its summary.
diagnose::LabDataset run_shear_curve(const json& doc) {
    diagnose::LabCurve c;
    c.kind = diagnose::CurveKind::Shear;
    c.confining_pa = doc.at("summary").value("sigma3_kPa", 0.0) * 1e3;
    for (const auto& r : doc.at("series").value("stress_strain", json::array())) {
        if (!r[0].is_number() || !r[1].is_number()) continue;
        c.axial_strain.push_back(r[0].get<double>() / 100.0);
        c.deviator_pa.push_back(r[1].get<double>() * 1e3);
    }
    diagnose::LabDataset d;
    d.curves.push_back(std::move(c));
    return d;
}

}  // namespace

void register_envelope_routes(Service& s) {
    s.route("GET", R"(/datasets/([^/]+)/envelope)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        json out = io::strength_envelope_json(load_dataset(s, id, nullptr));
        out["dataset_id"] = id;
        send_json(res, out);
    });
    s.route("GET", R"(/runs/([^/]+)/envelope)", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto id = path_id(req);
        const auto status = s.runs.status(id);  // 404 for an unknown run
        const auto doc = s.runs.result(id);
        if (!doc) throw conflict("run " + std::to_string(id) + " is " + status["status"].get<std::string>() +
                                 "; its envelope is known once it is done");
        json out = io::strength_envelope_json(run_shear_curve(*doc));
        out["run_id"] = id;
        send_json(res, out);
    });
}

}  // namespace triax::service
