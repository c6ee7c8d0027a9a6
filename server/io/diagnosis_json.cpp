// DiagnosisReport <-> JSON in lab units (see diagnosis_json.hpp).
#include "server/io/diagnosis_json.hpp"

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
        a.push_back({{"curve", e.curve}, {"phase", e.phase}, {"n", e.n}, {"rmse", e.rmse * u.factor},
                     {"unit", u.name}, {"nrmse", e.nrmse}});
    }
    return a;
}

std::vector<PhaseError> errors_from_json(const json& a) {
    std::vector<PhaseError> out;
    for (const auto& e : a) {
        double f = 1.0;
        const std::string unit = si_unit(e.at("unit").get<std::string>(), f);
        out.push_back({e.at("curve").get<std::string>(), e.at("phase").get<std::string>(), unit,
                       e.at("n").get<std::size_t>(), e.at("rmse").get<double>() * f, e.at("nrmse").get<double>()});
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

template <typename T>
T bounded(const json& body, const char* key, T lo, T hi, T fallback) {
    if (!body.contains(key)) return fallback;
    const json& v = body.at(key);
    const std::string pointer = std::string("/") + key;
    if (!v.is_number())
        throw DiagnosisRequestError(pointer, std::string(key) + " must be a number, got " + std::string(v.type_name()));
    if constexpr (std::is_integral_v<T>) {
        if (!v.is_number_integer() && !(v.is_number_float() && v.get<double>() == static_cast<double>(static_cast<long long>(v.get<double>()))))
            throw DiagnosisRequestError(pointer, std::string(key) + " must be an integer");
    }
    const double x = v.get<double>();
    if (x < static_cast<double>(lo) || x > static_cast<double>(hi))
        throw DiagnosisRequestError(pointer, std::string(key) + " must be between " + std::to_string(lo) + " and " +
                                                 std::to_string(hi) + ", got " + v.dump());
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
    for (const auto& s : r.steps)
        steps.push_back({{"step", s.step}, {"added", s.added}, {"nrmse_before", s.nrmse_before},
                         {"nrmse_after", s.nrmse_after}, {"delta_bic", s.delta_bic}, {"n_effective", s.n_effective}});
    return {{"chosen_effect", r.chosen_effect},
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
            {"runs_used", r.runs_used},
            {"verdict", r.verdict}};
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
    cr.bic = c.value("bic", 0.0);
    cr.delta_bic_vs_base = c.value("delta_bic_vs_base", 0.0);
    cr.note = c.value("note", std::string{});
    return cr;
}

DiagnosisReport diagnosis_report_from_json(const json& j) {
    DiagnosisReport r;
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
    for (const auto& s : j.value("steps", json::array()))
        r.steps.push_back({s.at("step").get<int>(), s.value("added", std::string{}), s.value("nrmse_before", 0.0),
                           s.value("nrmse_after", 0.0), s.value("delta_bic", 0.0), s.value("n_effective", 0.0)});
    r.n_readings = j.value("n_readings", 0.0);
    r.n_effective = j.value("n_effective", 0.0);
    r.runs_used = j.value("runs_used", 0);
    r.verdict = j.value("verdict", std::string{});
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
    o.concurrency = bounded(body, "concurrency", 1, 64, o.concurrency);
    o.threads_per_run = bounded(body, "threads_per_run", 1, 64, o.threads_per_run);
    o.max_particles = bounded(body, "max_particles", 0, 1000000, o.max_particles);
    o.seed = bounded<std::uint64_t>(body, "seed", 0, std::uint64_t{1} << 53, o.seed);
    o.bic_threshold = bounded(body, "bic_threshold", 0.0, 1e6, o.bic_threshold);
    o.finite_difference_uncertainty = flag(body, "finite_difference_uncertainty", o.finite_difference_uncertainty);
    return o;
}

json diagnose_options_to_json(const DiagnoseOptions& o) {
    return {{"budget_runs", o.budget_runs},
            {"refine_runs", o.refine_runs},
            {"max_candidates", o.max_candidates},
            {"max_effects", o.max_effects},
            {"concurrency", o.concurrency},
            {"threads_per_run", o.threads_per_run},
            {"max_particles", o.max_particles},
            {"seed", o.seed},
            {"bic_threshold", o.bic_threshold},
            {"finite_difference_uncertainty", o.finite_difference_uncertainty}};
}

}  // namespace triax::io
