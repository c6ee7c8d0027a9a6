// POST /comparisons {"run_id","dataset_id"[,"sigma3_kPa"]}, GET /comparisons, GET /comparisons/{id}.
// A run has one confining pressure: it is compared with the dataset's curves at that sigma3
// (2 % tolerance), or at the request's sigma3_kPa when given; the curves at other
// pressures are listed in `skipped`. A dataset with no curve at the run's sigma3 is
// compared whole, with a warning per pressure. Every row carries its lab curve's sigma3_kPa.
// Each lab curve compared is aligned with the run's matching series
// (diagnose::compare_curve: model interpolated at the lab abscissa) and the metrics and
// residuals are stored:
//   shear curve  -> stress_strain (q_kPa vs axial_strain_pct) and volumetric
//                   (volumetric_strain_pct vs axial_strain_pct) when measured;
//   creep stage k -> creep stage k (axial_deformation_mm vs time_min, or axial_strain_pct).
#include "engine/diagnose/metrics.hpp"
#include "server/http/paging.hpp"
#include "server/http/problem.hpp"
#include "server/runs/series.hpp"
#include "server/service.hpp"

#include <cmath>
#include <algorithm>
#include <set>
#include <sstream>

namespace triax::service {

using nlohmann::json;

namespace {

std::vector<double> column(const json& rows, std::size_t c, int stage = -1) {
    std::vector<double> out;
    for (const auto& r : rows) {
        if (stage >= 0 && !(r[0].is_number() && r[0].get<int>() == stage)) continue;
        out.push_back(r[c].is_number() ? r[c].get<double>() : NAN);
    }
    return out;
}

std::vector<double> scaled(const std::vector<double>& v, double f) {
    std::vector<double> out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i] * f;
    return out;
}

// Drops pairs with a missing value on either side.
void drop_missing(std::vector<double>& x, std::vector<double>& y) {
    std::vector<double> xs, ys;
    for (std::size_t i = 0; i < x.size() && i < y.size(); ++i)
        if (std::isfinite(x[i]) && std::isfinite(y[i])) { xs.push_back(x[i]); ys.push_back(y[i]); }
    x = std::move(xs);
    y = std::move(ys);
}

// "50 kPa", "12.5 kPa": a pressure as a lab sheet writes it (4 significant digits at most).
std::string kpa_text(double kpa) {
    std::ostringstream o;
    o.precision(4);
    o << kpa << " kPa";
    return o.str();
}

bool same_pressure(double a_kpa, double b_kpa) { return std::abs(a_kpa - b_kpa) <= 0.02 * std::max(a_kpa, b_kpa); }

json metrics_json(double sigma3_kpa, const char* curve, json stage, const char* xname, const char* yname, const char* unit,
                  const diagnose::CurveMetrics& m) {
    json residual = json::array();
    for (const auto& p : m.points) residual.push_back({p.x, p.model, p.lab, p.residual});
    return {{"sigma3_kPa", sigma3_kpa}, {"curve", curve}, {"stage", stage}, {"x", xname}, {"y", yname}, {"unit", unit},
            {"n", m.n}, {"dropped", m.dropped}, {"rmse", m.rmse}, {"nrmse", m.nrmse}, {"r2", m.r2},
            {"max_error", m.max_error}, {"residual", residual}};
}

// wanted_kpa: the lab sigma3 asked for (0: the run's when the dataset has it, else all).
json compare(Service& s, std::int64_t run_id, std::int64_t dataset_id, double wanted_kpa) {
    const auto status = s.runs.status(run_id);
    const auto doc = s.runs.result(run_id);
    if (!doc)
        throw conflict("run " + std::to_string(run_id) + " is " + status["status"].get<std::string>() +
                       "; compare a run that is done")
            .at_field("/run_id");
    const auto dataset = load_dataset(s, dataset_id, nullptr);
    const json& series = doc->at("series");
    const json& summary = doc->at("summary");
    json curves = json::array(), skipped = json::array(), warnings = json::array();
    const double sigma3_kpa = summary.value("sigma3_kPa", 0.0);
    std::set<double> pressures;
    for (const auto& c : dataset.curves) pressures.insert(c.confining_pa * 1e-3);
    bool run_pressure_in_lab = false;
    for (double p : pressures) run_pressure_in_lab = run_pressure_in_lab || (sigma3_kpa > 0 && same_pressure(p, sigma3_kpa));
    if (wanted_kpa > 0) {
        bool found = false;
        for (double p : pressures) found = found || same_pressure(p, wanted_kpa);
        if (!found)
            throw unprocessable("dataset " + std::to_string(dataset_id) + " has no curve at " + kpa_text(wanted_kpa))
                .at_field("/sigma3_kPa");
    }
    const double lab_kpa = wanted_kpa > 0 ? wanted_kpa : run_pressure_in_lab ? sigma3_kpa : 0.0;
    std::set<double> warned;

    for (const auto& c : dataset.curves) {
        const double lab_sigma3 = c.confining_pa * 1e-3;
        const bool shear = c.kind == diagnose::CurveKind::Shear;
        if (lab_kpa > 0 && !same_pressure(lab_sigma3, lab_kpa)) {
            skipped.push_back(json{{"sigma3_kPa", lab_sigma3}, {"curve", shear ? "stress_strain" : "creep"},
                                   {"stage", shear ? json(nullptr) : json(c.stage)},
                                   {"reason", "lab curve at " + kpa_text(lab_sigma3) + "; compared at " + kpa_text(lab_kpa)}});
            continue;
        }
        if (sigma3_kpa > 0 && !same_pressure(lab_sigma3, sigma3_kpa) && warned.insert(lab_sigma3).second)
            warnings.push_back("lab curve at " + kpa_text(lab_sigma3) + " confining vs run at " + kpa_text(sigma3_kpa));
        if (c.kind == diagnose::CurveKind::Shear) {
            if (c.axial_strain.empty()) {
                skipped.push_back(json{{"sigma3_kPa", lab_sigma3}, {"curve", "stress_strain"}, {"stage", nullptr}, {"reason", "no axial strain measured"}});
                continue;
            }
            const auto lab_x = scaled(c.axial_strain, 100.0);
            if (!c.deviator_pa.empty()) {
                auto mx = column(series["stress_strain"], 0), my = column(series["stress_strain"], 1);
                drop_missing(mx, my);
                if (mx.size() < 2) skipped.push_back(json{{"sigma3_kPa", lab_sigma3}, {"curve", "stress_strain"}, {"stage", nullptr}, {"reason", "the run has no shear curve"}});
                else curves.push_back(metrics_json(lab_sigma3, "stress_strain", nullptr, "axial_strain_pct", "q_kPa", "kPa",
                                                   diagnose::compare_curve(mx, my, lab_x, scaled(c.deviator_pa, 1e-3))));
            }
            if (!c.volumetric_strain.empty()) {
                auto mx = column(series["volumetric"], 0), my = column(series["volumetric"], 1);
                drop_missing(mx, my);
                if (mx.size() < 2) skipped.push_back(json{{"sigma3_kPa", lab_sigma3}, {"curve", "volumetric"}, {"stage", nullptr}, {"reason", "the run has no volumetric curve"}});
                else curves.push_back(metrics_json(lab_sigma3, "volumetric", nullptr, "axial_strain_pct", "volumetric_strain_pct", "%",
                                                   diagnose::compare_curve(mx, my, lab_x, scaled(c.volumetric_strain, 100.0))));
            }
        } else {
            if (c.time_s.empty() || (c.axial_deformation_m.empty() && c.axial_strain.empty())) {
                skipped.push_back(json{{"sigma3_kPa", lab_sigma3}, {"curve", "creep"}, {"stage", c.stage}, {"reason", "needs time and axial deformation or strain"}});
                continue;
            }
            const bool by_deformation = !c.axial_deformation_m.empty();
            auto mx = column(series["creep"], 1, c.stage);
            auto my = column(series["creep"], by_deformation ? 2 : 3, c.stage);
            drop_missing(mx, my);
            if (mx.size() < 2) {
                skipped.push_back(json{{"sigma3_kPa", lab_sigma3}, {"curve", "creep"}, {"stage", c.stage}, {"reason", "the run has no creep stage " + std::to_string(c.stage)}});
                continue;
            }
            const auto lab_y = by_deformation ? scaled(c.axial_deformation_m, 1e3) : scaled(c.axial_strain, 100.0);
            curves.push_back(metrics_json(lab_sigma3, "creep", c.stage, "time_min",
                                          by_deformation ? "axial_deformation_mm" : "axial_strain_pct",
                                          by_deformation ? "mm" : "%",
                                          diagnose::compare_curve(mx, my, scaled(c.time_s, 1.0 / 60.0), lab_y)));
        }
    }
    if (curves.empty())
        throw unprocessable("no curve of dataset " + std::to_string(dataset_id) + " could be aligned with run " +
                            std::to_string(run_id))
            .at_field("/dataset_id");
    return {{"run_sigma3_kPa", sigma3_kpa}, {"lab_sigma3_kPa", lab_kpa > 0 ? json(lab_kpa) : json(nullptr)},
            {"curves", curves}, {"skipped", skipped}, {"warnings", warnings}};
}

}  // namespace

void register_comparison_routes(Service& s) {
    s.route("POST", "/comparisons", [&s](const httplib::Request& req, httplib::Response& res) {
        const auto body = parse_body(req);
        if (!body.is_object()) throw unprocessable("the body must be {\"run_id\":..,\"dataset_id\":..}").at_field("");
        for (const char* k : {"run_id", "dataset_id"})
            if (!body.contains(k) || !body[k].is_number_integer() || body[k].get<long long>() < 1)
                throw unprocessable(std::string(k) + " must be a positive integer").at_field(std::string("/") + k);
        const auto run_id = body["run_id"].get<std::int64_t>(), dataset_id = body["dataset_id"].get<std::int64_t>();
        if (!s.runs.exists(run_id)) throw not_found("run " + std::to_string(run_id) + " does not exist").at_field("/run_id");
        double wanted_kpa = 0.0;
        if (body.contains("sigma3_kPa") && !body["sigma3_kPa"].is_null()) {
            if (!body["sigma3_kPa"].is_number() || !(body["sigma3_kPa"].get<double>() > 0.0))
                throw unprocessable("sigma3_kPa must be a positive number (kPa) or null").at_field("/sigma3_kPa");
            wanted_kpa = body["sigma3_kPa"].get<double>();
        }
        json result = compare(s, run_id, dataset_id, wanted_kpa);
        const auto created = utc_now();
        const auto id = s.comparisons.insert(run_id, dataset_id, result, created);
        result["id"] = id;
        result["run_id"] = run_id;
        result["dataset_id"] = dataset_id;
        result["created_at"] = created;
        res.set_header("Location", "/comparisons/" + std::to_string(id));
        send_json(res, result, 201);
    });
    s.route("GET", "/comparisons", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.comparisons.page(page_request(req)));
    });
    s.route("GET", R"(/comparisons/([^/]+))", [&s](const httplib::Request& req, httplib::Response& res) {
        send_json(res, s.comparisons.get(path_id(req)));
    });
}

}  // namespace triax::service
