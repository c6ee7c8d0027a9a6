// DiagnosisReport <-> JSON in lab units (see diagnosis_json.hpp).
#include "server/io/diagnosis_json.hpp"

#include <cmath>

#include "server/io/diagnosis_verdict.hpp"
#include "server/io/strength_envelope_json.hpp"

namespace triax::io {

using nlohmann::json;
using namespace triax::diagnose;

namespace {

// SI -> lab unit for curve errors: Pa -> kPa, strain [-] -> %, deformation m -> mm.
struct LabUnit { std::string name; double factor; };
LabUnit lab_unit(const std::string& si) {
    if (si == "Pa") return {"kPa", 1e-3};
    if (si == "-") return {"%", 100.0};
    if (si == "m") return {"mm", 1e3};
    return {si, 1.0};
}
std::string si_unit(const std::string& lab, double& factor) {
    if (lab == "kPa") return factor = 1e3, "Pa";
    if (lab == "%") return factor = 1e-2, "-";
    if (lab == "mm") return factor = 1e-3, "m";
    factor = 1.0;
    return lab;
}

json errors_to_json(const std::vector<PhaseError>& errors) {
    json a = json::array();
    for (const auto& e : errors) {
        const auto u = lab_unit(e.unit);
        a.push_back({{"curve", e.curve}, {"phase", e.phase}, {"n", e.n}, {"n_unreached", e.n_unreached},
                     {"rmse", e.rmse * u.factor}, {"unit", u.name}, {"nrmse", e.nrmse}});
    }
    return a;
}

std::vector<PhaseError> errors_from_json(const json& a) {
    std::vector<PhaseError> out;
    for (const auto& e : a) {
        double f = 1.0;
        const std::string unit = si_unit(e.at("unit").get<std::string>(), f);
        out.push_back({e.at("curve").get<std::string>(), e.at("phase").get<std::string>(), unit,
                       e.at("n").get<std::size_t>(), e.value("n_unreached", std::size_t{0}), e.at("rmse").get<double>() * f,
                       e.at("nrmse").get<double>()});
    }
    return out;
}

json parameters_to_json(const std::vector<FittedParameter>& ps) {
    json a = json::array();
    for (const auto& p : ps) a.push_back({{"name", p.name}, {"unit", p.unit}, {"value", p.value}, {"std", p.std}});
    return a;
}

std::vector<FittedParameter> parameters_from_json(const json& a) {
    std::vector<FittedParameter> out;
    for (const auto& p : a)
        out.push_back({p.at("name").get<std::string>(), p.value("unit", std::string{}), p.at("value").get<double>(),
                       p.value("std", 0.0)});
    return out;
}

json scaled(const std::vector<double>& v, double f) {
    json a = json::array();
    for (double x : v) a.push_back(x * f);
    return a;
}

std::vector<double> unscaled(const json& a, double f) {
    std::vector<double> v;
    for (const auto& x : a) v.push_back(x.get<double>() / f);
    return v;
}

// Model curves in lab units (kPa, %, mm, min), compression positive.
json curves_to_json(const LabDataset& d) {
    json a = json::array();
    for (const auto& c : d.curves) {
        json j{{"kind", c.kind == CurveKind::Shear ? "shear" : "creep"}, {"stage", c.stage},
               {"confining_kPa", c.confining_pa * 1e-3}, {"stress_level", c.stress_level}};
        if (!c.axial_strain.empty()) j["axial_strain_pct"] = scaled(c.axial_strain, 100.0);
        if (!c.deviator_pa.empty()) j["deviator_kPa"] = scaled(c.deviator_pa, 1e-3);
        if (!c.volumetric_strain.empty()) j["volumetric_strain_pct"] = scaled(c.volumetric_strain, 100.0);
        if (!c.time_s.empty()) j["time_min"] = scaled(c.time_s, 1.0 / 60.0);
        if (!c.axial_deformation_m.empty()) j["axial_deformation_mm"] = scaled(c.axial_deformation_m, 1e3);
        a.push_back(std::move(j));
    }
    return a;
}

LabDataset curves_from_json(const json& a) {
    LabDataset d;
    for (const auto& j : a) {
        LabCurve c;
        c.kind = j.value("kind", std::string{"shear"}) == "creep" ? CurveKind::Creep : CurveKind::Shear;
        c.stage = j.value("stage", 0);
        c.confining_pa = j.value("confining_kPa", 0.0) * 1e3;
        c.stress_level = j.value("stress_level", 0.0);
        if (j.contains("axial_strain_pct")) c.axial_strain = unscaled(j["axial_strain_pct"], 100.0);
        if (j.contains("deviator_kPa")) c.deviator_pa = unscaled(j["deviator_kPa"], 1e-3);
        if (j.contains("volumetric_strain_pct")) c.volumetric_strain = unscaled(j["volumetric_strain_pct"], 100.0);
        if (j.contains("time_min")) c.time_s = unscaled(j["time_min"], 1.0 / 60.0);
        if (j.contains("axial_deformation_mm")) c.axial_deformation_m = unscaled(j["axial_deformation_mm"], 1e3);
        d.curves.push_back(std::move(c));
    }
    return d;
}

template <typename T>
T bounded(const json& body, const char* key, T lo, T hi, T fallback) {
    if (!body.contains(key)) return fallback;
    const json& v = body.at(key);
    const std::string pointer = std::string("/") + key;
    if (!v.is_number())
        throw DiagnosisRequestError(pointer, std::string(key) + " must be a number, got " + std::string(v.type_name()));
    // Range first (as a double, never cast out of range), then integrality.
    const double x = v.get<double>();
    if (!(x >= static_cast<double>(lo) && x <= static_cast<double>(hi)))
        throw DiagnosisRequestError(pointer, std::string(key) + " must be between " + json(lo).dump() + " and " +
                                                 json(hi).dump() + ", got " + v.dump());
    if constexpr (std::is_integral_v<T>) {
        if (std::floor(x) != x) throw DiagnosisRequestError(pointer, std::string(key) + " must be an integer");
        if (v.is_number_integer()) return v.get<T>();
    }
    return static_cast<T>(x);
}

bool flag(const json& body, const char* key, bool fallback) {
    if (!body.contains(key)) return fallback;
    const json& v = body.at(key);
    if (!v.is_boolean())
        throw DiagnosisRequestError(std::string("/") + key,
                                    std::string(key) + " must be true or false, got " + std::string(v.type_name()));
    return v.get<bool>();
}

}  // namespace

json candidate_to_json(const CandidateResult& c) {
    return {{"step", c.step},
            {"effect", c.effect},
            {"signature_score", c.signature_score},
            {"fitted", c.fitted},
            {"parameters", parameters_to_json(c.parameters)},
            {"rss", c.rss},
            {"nrmse", c.nrmse},
            {"paired_gains", c.paired_gains},
            {"bic", c.bic},
            {"delta_bic_vs_base", c.delta_bic_vs_base},
            {"note", c.note}};
}

json diagnosis_report_to_json(const DiagnosisReport& r) {
    json runners = json::array();
    for (const auto& ru : r.runners_up) runners.push_back({{"effect", ru.effect}, {"delta_bic", ru.delta_bic}});
    json candidates = json::array();
    for (const auto& c : r.candidates) candidates.push_back(candidate_to_json(c));
    json steps = json::array();
    for (const auto& s : r.steps) {
        json by_pressure = json::array();
        for (const auto& [pa, gain] : s.gain_by_confining)
            by_pressure.push_back({{"sigma3_kPa", pa / 1000.0}, {"nrmse_gain", gain}});
        steps.push_back({{"step", s.step}, {"added", s.added}, {"nrmse_before", s.nrmse_before},
                         {"nrmse_after", s.nrmse_after}, {"delta_bic", s.delta_bic}, {"n_effective", s.n_effective},
                         {"paired_gains", s.paired_gains}, {"gain_by_sigma3", by_pressure}});
    }
    json held = json::array();
    for (const auto& h : r.held_fixed) held.push_back({{"name", h.name}, {"unit", h.unit}, {"value", h.value}, {"why", h.why}});
    json untested = json::array();
    for (const auto& t : r.not_testable) untested.push_back({{"effect", t.effect}, {"reason", t.reason}});
    json bounds = json::array();
    for (const auto& b : r.at_bounds)
        bounds.push_back({{"name", b.name}, {"unit", b.unit}, {"value", b.value}, {"bound", b.upper ? "upper" : "lower"}});
    json per_curve = json::object();
    for (const auto& [label, v] : r.noise.model_nrmse_per_curve) per_curve[label] = v;
    json per_kind = json::object();
    for (const auto& [kind, v] : r.noise.model_nrmse_per_kind) per_kind[kind] = v;
    json fit_weights = json::object();
    for (const auto& [kind, v] : r.fit_weights) fit_weights[kind] = v;
    const auto worst = errors_to_json({r.worst_remaining});
    return {{"outcome", std::string(outcome_name(r.outcome))},
            {"chosen_effect", r.chosen_effect},
            {"effects", r.effects},
            {"parameters", parameters_to_json(r.parameters)},
            {"base_parameters", parameters_to_json(r.base_parameters)},
            {"error_before", errors_to_json(r.error_before)},
            {"error_after", errors_to_json(r.error_after)},
            {"nrmse_before", r.nrmse_before},
            {"nrmse_after", r.nrmse_after},
            {"delta_bic", {{"vs_base", r.delta_bic_vs_base}, {"runners_up", runners}}},
            {"candidates", candidates},
            {"steps", steps},
            {"n_readings", r.n_readings},
            {"n_effective", r.n_effective},
            {"unreached_before", r.unreached_before},
            {"unreached_after", r.unreached_after},
            {"noise_floor", {{"seeds", r.noise.seeds},
                             {"model_nrmse", r.noise.model_nrmse},
                             {"lab_nrmse", r.noise.lab_nrmse},
                             {"tolerance_nrmse", r.noise.tolerance_nrmse},
                             {"smallest_nameable_gain_nrmse", r.noise.smallest_nameable_gain},
                             {"model_nrmse_per_curve", per_curve},
                             {"model_nrmse_per_kind", per_kind}}},
            {"fit_weight_per_kind", fit_weights},
            {"worst_remaining", r.worst_remaining.curve.empty() ? json(nullptr) : worst[0]},
            {"held_fixed", held},
            {"not_testable", untested},
            {"at_bounds", bounds},
            {"artefacts_below_threshold", r.artefacts_below_threshold},
            {"artefacts_dropped", r.artefacts_dropped},
            {"base_curves", curves_to_json(r.base_curves)},
            {"final_curves", curves_to_json(r.final_curves)},
            // Mohr circles and the Mohr-Coulomb fit of the model's peaks over the lab's sigma3
            // set: the calibrated base's and the final model's c' and phi'.
            {"strength_envelope", {{"base", strength_envelope_json(r.base_curves)},
                                   {"final", strength_envelope_json(r.final_curves)}}},
            {"runs_used", r.runs_used},
            {"failed_runs", r.failed_runs},
            {"retried_runs", r.retried_runs},
            {"failure_messages", r.failure_messages},
            {"verdict", diagnosis_verdict(r)}};
}

CandidateResult candidate_from_json(const json& c) {
    CandidateResult cr;
    cr.step = c.value("step", 1);
    cr.effect = c.at("effect").get<std::string>();
    cr.signature_score = c.value("signature_score", 0.0);
    cr.fitted = c.value("fitted", false);
    cr.parameters = parameters_from_json(c.value("parameters", json::array()));
    cr.rss = c.value("rss", 0.0);
    cr.nrmse = c.value("nrmse", 0.0);
    cr.paired_gains = c.value("paired_gains", std::vector<double>{});
    cr.bic = c.value("bic", 0.0);
    cr.delta_bic_vs_base = c.value("delta_bic_vs_base", 0.0);
    cr.note = c.value("note", std::string{});
    return cr;
}

DiagnosisReport diagnosis_report_from_json(const json& j) {
    DiagnosisReport r;
    const std::string outcome = j.value("outcome", std::string{"unexplained"});
    r.outcome = outcome == "effect_found" ? Outcome::EffectFound
                : outcome == "no_effect_needed" ? Outcome::NoEffectNeeded
                                               : Outcome::Unexplained;
    r.chosen_effect = j.at("chosen_effect").get<std::string>();
    r.effects = j.value("effects", std::vector<std::string>{});
    r.parameters = parameters_from_json(j.at("parameters"));
    r.base_parameters = parameters_from_json(j.value("base_parameters", json::array()));
    r.error_before = errors_from_json(j.at("error_before"));
    r.error_after = errors_from_json(j.at("error_after"));
    r.nrmse_before = j.value("nrmse_before", 0.0);
    r.nrmse_after = j.value("nrmse_after", 0.0);
    const json& d = j.at("delta_bic");
    r.delta_bic_vs_base = d.at("vs_base").get<double>();
    for (const auto& ru : d.value("runners_up", json::array()))
        r.runners_up.push_back({ru.at("effect").get<std::string>(), ru.at("delta_bic").get<double>()});
    for (const auto& c : j.value("candidates", json::array())) r.candidates.push_back(candidate_from_json(c));
    for (const auto& s : j.value("steps", json::array())) {
        SelectionStep st{s.at("step").get<int>(), s.value("added", std::string{}), s.value("nrmse_before", 0.0),
                         s.value("nrmse_after", 0.0), s.value("delta_bic", 0.0), s.value("n_effective", 0.0),
                         s.value("paired_gains", std::vector<double>{}), {}};
        for (const auto& g : s.value("gain_by_sigma3", json::array()))
            st.gain_by_confining.emplace_back(g.at("sigma3_kPa").get<double>() * 1000.0, g.at("nrmse_gain").get<double>());
        r.steps.push_back(std::move(st));
    }
    r.n_readings = j.value("n_readings", 0.0);
    r.n_effective = j.value("n_effective", 0.0);
    r.runs_used = j.value("runs_used", 0);
    r.unreached_before = j.value("unreached_before", std::size_t{0});
    r.unreached_after = j.value("unreached_after", std::size_t{0});
    if (j.contains("noise_floor")) {
        const json& n = j["noise_floor"];
        r.noise.seeds = n.value("seeds", 0);
        r.noise.model_nrmse = n.value("model_nrmse", 0.0);
        r.noise.lab_nrmse = n.value("lab_nrmse", 0.0);
        r.noise.tolerance_nrmse = n.value("tolerance_nrmse", 0.0);
        r.noise.smallest_nameable_gain = n.value("smallest_nameable_gain_nrmse", 0.0);
        // A named copy: items() over value()'s temporary would read it after its end.
        const json per_curve = n.value("model_nrmse_per_curve", json::object());
        for (const auto& [label, v] : per_curve.items()) r.noise.model_nrmse_per_curve.emplace_back(label, v.get<double>());
        const json per_kind = n.value("model_nrmse_per_kind", json::object());
        for (const auto& [kind, v] : per_kind.items()) r.noise.model_nrmse_per_kind.emplace_back(kind, v.get<double>());
    }
    const json fit_weights = j.value("fit_weight_per_kind", json::object());
    for (const auto& [kind, v] : fit_weights.items()) r.fit_weights.emplace_back(kind, v.get<double>());
    if (j.contains("worst_remaining") && j["worst_remaining"].is_object())
        r.worst_remaining = errors_from_json(json::array({j["worst_remaining"]})).front();
    for (const auto& h : j.value("held_fixed", json::array()))
        r.held_fixed.push_back({h.at("name").get<std::string>(), h.value("unit", std::string{}), h.value("value", 0.0),
                                h.value("why", std::string{})});
    for (const auto& t : j.value("not_testable", json::array()))
        r.not_testable.push_back({t.at("effect").get<std::string>(), t.value("reason", std::string{})});
    for (const auto& b : j.value("at_bounds", json::array()))
        r.at_bounds.push_back({b.at("name").get<std::string>(), b.value("unit", std::string{}), b.value("value", 0.0),
                               b.value("bound", std::string{}) == "upper"});
    r.artefacts_below_threshold = j.value("artefacts_below_threshold", std::vector<std::string>{});
    r.artefacts_dropped = j.value("artefacts_dropped", std::vector<std::string>{});
    r.base_curves = curves_from_json(j.value("base_curves", json::array()));
    r.final_curves = curves_from_json(j.value("final_curves", json::array()));
    r.failed_runs = j.value("failed_runs", 0);
    r.retried_runs = j.value("retried_runs", 0);
    r.failure_messages = j.value("failure_messages", std::vector<std::string>{});
    return r;
}

DiagnoseOptions diagnose_options_from_json(const json& body) {
    DiagnoseOptions o;
    if (body.is_null()) return o;  // no options given: all defaults
    if (!body.is_object()) throw DiagnosisRequestError("", "diagnose options must be a JSON object");
    o.budget_runs = bounded(body, "budget_runs", 4, 400, o.budget_runs);
    o.refine_runs = bounded(body, "refine_runs", 1, 100, o.refine_runs);
    o.max_candidates = bounded(body, "max_candidates", 1, 6, o.max_candidates);
    o.max_effects = bounded(body, "max_effects", 1, 6, o.max_effects);
    o.batch_runs = bounded(body, "batch_runs", 1, 16, o.batch_runs);
    o.concurrency = bounded(body, "concurrency", 1, 64, o.concurrency);
    o.threads_per_run = bounded(body, "threads_per_run", 1, 64, o.threads_per_run);
    o.max_particles = bounded(body, "max_particles", 0, 1000000, o.max_particles);
    o.packings_per_run = bounded(body, "packings_per_run", 1, 16, o.packings_per_run);
    // The lab specimen's relative density in % (lab units), absent or null when not stated.
    if (body.contains("relative_density_percent") && !body["relative_density_percent"].is_null())
        o.relative_density = bounded(body, "relative_density_percent", 0.0, 100.0, 0.0) / 100.0;
    o.seed = bounded<std::uint64_t>(body, "seed", 0, std::uint64_t{1} << 53, o.seed);
    o.noise_seeds = bounded(body, "noise_seeds", 1, 16, o.noise_seeds);
    o.bic_threshold = bounded(body, "bic_threshold", 0.0, 1e6, o.bic_threshold);
    o.finite_difference_uncertainty = flag(body, "finite_difference_uncertainty", o.finite_difference_uncertainty);
    return o;
}

json diagnose_options_to_json(const DiagnoseOptions& o) {
    json j{{"budget_runs", o.budget_runs},
            {"refine_runs", o.refine_runs},
            {"max_candidates", o.max_candidates},
            {"max_effects", o.max_effects},
            {"batch_runs", o.batch_runs},
            {"concurrency", o.concurrency},
            {"threads_per_run", o.threads_per_run},
            {"max_particles", o.max_particles},
            {"packings_per_run", o.packings_per_run},
            {"seed", o.seed},
            {"noise_seeds", o.noise_seeds},
            {"bic_threshold", o.bic_threshold},
            {"finite_difference_uncertainty", o.finite_difference_uncertainty}};
    j["relative_density_percent"] = o.relative_density ? json(100.0 * *o.relative_density) : json(nullptr);
    return j;
}

}  // namespace triax::io
