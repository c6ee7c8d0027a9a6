#include "server/io/scheme_json.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include "engine/core/types.hpp"
#include "server/io/scheme_fields.hpp"

namespace triax::io {

using nlohmann::json;
using protocol::TestScheme;

namespace {

// Length limits of a scheme document: a name is a label, a stress-level list or sieve
// curve a few dozen entries in any lab practice.
constexpr std::size_t kMaxSchemeNameBytes = 200;
constexpr std::size_t kMaxSchemeArray = 100;

std::string ptr(const std::string& section, const std::string& key) { return "/" + section + "/" + key; }

double number_at(const json& v, const std::string& pointer) {
    if (!v.is_number()) throw SchemeError(pointer, "must be a number, got " + std::string(v.type_name()));
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw SchemeError(pointer, "must be finite");
    return d;
}

// A lab value converted to SI; 1e308 MPa is a finite JSON number but not a finite pascal.
double si_number_at(const json& v, const std::string& pointer, double to_si) {
    const double si = to_si * number_at(v, pointer);
    if (!std::isfinite(si)) throw SchemeError(pointer, "beyond the range of this field (not finite in SI units)");
    return si;
}

std::vector<double> number_array(const json& v, const std::string& pointer, double to_si) {
    if (!v.is_array()) throw SchemeError(pointer, "must be an array of numbers");
    if (v.size() > kMaxSchemeArray)
        throw SchemeError(pointer, "at most " + std::to_string(kMaxSchemeArray) + " entries");
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) out.push_back(si_number_at(v[i], pointer + "/" + std::to_string(i), to_si));
    return out;
}

// An integer field read whole: 2^63 must not wrap to a negative int.
long long integer_at(const json& v, const std::string& pointer, long long lo, long long hi) {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!v.is_number_integer()) throw SchemeError(pointer, "must be an integer in " + range);
    const bool too_big = v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi);
    const long long n = too_big ? hi : v.get<long long>();
    if (too_big || n < lo || n > hi) throw SchemeError(pointer, "must be an integer in " + range + ", got " + v.dump());
    return n;
}

// Maps a TestScheme::validate dotted name ("loading.stress_levels[2]") to a JSON pointer.
std::string pointer_for(const std::string& si_field) {
    std::string base = si_field, index;
    if (auto b = si_field.find('['); b != std::string::npos) {
        base = si_field.substr(0, b);
        index = si_field.substr(b + 1, si_field.find(']') - b - 1);
    }
    for (const auto& f : number_fields())
        if (base == f.si_name) return ptr(f.section, f.key);
    static const std::map<std::string, std::string> others = {
        {"loading.stress_levels", "/loading/stress_levels"},
        {"loading.stage_durations_s", "/loading/stage_durations_min"},
        {"gradation.sieve_curve", "/gradation/sieve_curve"},
        {"gradation", "/gradation"},
        {"threads", "/threads"},
        {"max_particles", "/max_particles"},
    };
    std::string p = others.count(base) ? others.at(base) : "/" + base;
    if (!index.empty()) p += "/" + index;
    return p;
}

// A stored document may carry the retired pair effects.rolling_resistance and
// effects.rolling_friction (0.1 when absent): with the switch on, its value is the
// contacts' mu_r (micro.rolling_friction); off, micro.rolling_friction stands.
void read_retired_rolling(const json& j, TestScheme& s) {
    if (!j.contains("effects") || !j["effects"].contains("rolling_resistance")) return;
    const auto& fx = j["effects"];
    if (!fx["rolling_resistance"].is_boolean())
        throw SchemeError("/effects/rolling_resistance", "must be true or false");
    if (!fx["rolling_resistance"].get<bool>()) return;
    s.micro.rolling_friction =
        fx.contains("rolling_friction") ? number_at(fx["rolling_friction"], "/effects/rolling_friction") : 0.1;
}

// The engine's InputError reads "field: why" (TestScheme::validate, paper_group); one
// without a field stands whole for both.
struct EngineMessage {
    std::string field, why;
};
EngineMessage engine_message(const InputError& e) {
    const std::string msg = e.what();
    const auto colon = msg.find(':');
    if (colon == std::string::npos) return {msg, msg};
    return {msg.substr(0, colon), msg.substr(colon + 2)};
}

}  // namespace

TestScheme scheme_from_json(const json& j) {
    if (!j.is_object()) throw SchemeError("", "a scheme must be a JSON object");
    const auto is_section = [](const std::string& k) {
        return std::find(std::begin(kSchemeSections), std::end(kSchemeSections), k) != std::end(kSchemeSections);
    };
    // A field of `section` ("" = the top level) that some table names.
    const auto known = [](const std::string& section, const std::string& k) {
        const auto is = [&](const auto& f) { return section == f.section && k == f.key; };
        return std::any_of(number_fields().begin(), number_fields().end(), is) ||
               std::any_of(bool_fields().begin(), bool_fields().end(), is) ||
               std::any_of(shaped_fields().begin(), shaped_fields().end(), is) ||
               std::any_of(retired_fields().begin(), retired_fields().end(), is);
    };
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& k = it.key();
        if (known("", k)) continue;
        if (!is_section(k)) throw SchemeError("/" + k, "unknown field");
        if (!it.value().is_object()) throw SchemeError("/" + k, "must be an object");
    }
    // A scheme may start from a paper group (Table 2 with the presets' micro-parameters) and
    // change only what differs, e.g. {"preset": "C", "seed": 3}; without it, the bare
    // defaults of TestScheme.
    TestScheme s;
    if (j.contains("preset")) {
        if (!j["preset"].is_string()) throw SchemeError("/preset", "must be the name of a paper group (GET /presets)");
        try {
            s = protocol::paper_group(j["preset"].get<std::string>());
        } catch (const InputError& e) {  // the engine's lookup names the valid groups
            throw SchemeError("/preset", engine_message(e).why);
        }
    }
    if (j.contains("name")) {
        if (!j["name"].is_string()) throw SchemeError("/name", "must be a string");
        s.name = j["name"].get<std::string>();
        if (s.name.size() > kMaxSchemeNameBytes)
            throw SchemeError("/name", "must be at most " + std::to_string(kMaxSchemeNameBytes) + " bytes");
    }
    if (j.contains("seed")) {
        if (!j["seed"].is_number_integer() || j["seed"].get<long long>() < 0)
            throw SchemeError("/seed", "must be a non-negative integer");
        s.seed = j["seed"].get<std::uint64_t>();
    }
    if (j.contains("threads")) s.threads = static_cast<int>(integer_at(j["threads"], "/threads", 1, 256));
    if (j.contains("max_particles"))
        s.max_particles = static_cast<int>(integer_at(j["max_particles"], "/max_particles", 0, 100'000'000));
    // Unknown keys inside sections.
    for (const char* sec : kSchemeSections) {
        if (!j.contains(sec)) continue;
        for (auto it = j[sec].begin(); it != j[sec].end(); ++it)
            if (!known(sec, it.key())) throw SchemeError(ptr(sec, it.key()), "unknown field");
    }
    for (const auto& f : number_fields()) {
        if (!j.contains(f.section) || !j[f.section].contains(f.key)) continue;
        f.ref(s) = si_number_at(j[f.section][f.key], ptr(f.section, f.key), f.to_si);
    }
    for (const auto& f : bool_fields()) {
        if (!j.contains(f.section) || !j[f.section].contains(f.key)) continue;
        const auto& v = j[f.section][f.key];
        if (!v.is_boolean()) throw SchemeError(ptr(f.section, f.key), "must be true or false");
        f.ref(s) = v.get<bool>();
    }
    read_retired_rolling(j, s);
    if (j.contains("specimen") && j["specimen"].contains("lateral_boundary")) {
        const auto& b = j["specimen"]["lateral_boundary"];
        if (b == "bonded_membrane") s.specimen.lateral_boundary = protocol::SpecimenSpec::LateralBoundary::BondedMembrane;
        else if (b == "grain_pressure") s.specimen.lateral_boundary = protocol::SpecimenSpec::LateralBoundary::GrainPressure;
        else throw SchemeError("/specimen/lateral_boundary", "must be \"bonded_membrane\" or \"grain_pressure\"");
    }
    if (j.contains("gradation")) {
        const auto& g = j["gradation"];
        if (g.contains("kind")) {
            const auto& k = g["kind"];
            if (k == "radius_ratio") s.gradation.kind = protocol::GradationSpec::Kind::RadiusRatio;
            else if (k == "sieve_curve") s.gradation.kind = protocol::GradationSpec::Kind::SieveCurve;
            else throw SchemeError("/gradation/kind", "must be \"radius_ratio\" or \"sieve_curve\"");
        } else if (g.contains("sieve_curve")) {
            s.gradation.kind = protocol::GradationSpec::Kind::SieveCurve;
        }
        if (g.contains("sieve_curve")) {
            const auto& c = g["sieve_curve"];
            if (!c.is_array()) throw SchemeError("/gradation/sieve_curve", "must be an array of {size_mm, passing_pct}");
            if (c.size() > kMaxSchemeArray)
                throw SchemeError("/gradation/sieve_curve", "at most " + std::to_string(kMaxSchemeArray) + " points");
            for (std::size_t i = 0; i < c.size(); ++i) {
                const std::string p = "/gradation/sieve_curve/" + std::to_string(i);
                if (!c[i].is_object() || !c[i].contains("size_mm") || !c[i].contains("passing_pct"))
                    throw SchemeError(p, "must be an object {size_mm, passing_pct}");
                s.gradation.sieve_curve.push_back({1e-3 * number_at(c[i]["size_mm"], p + "/size_mm"),
                                                   number_at(c[i]["passing_pct"], p + "/passing_pct")});
            }
        }
    }
    if (j.contains("loading")) {
        const auto& l = j["loading"];
        if (l.contains("stress_levels")) s.loading.stress_levels = number_array(l["stress_levels"], "/loading/stress_levels", 1.0);
        if (l.contains("stage_durations_min"))
            s.loading.stage_durations_s = number_array(l["stage_durations_min"], "/loading/stage_durations_min", 60.0);
        else if (l.contains("stress_levels")) {  // one default (or the preset's) duration per stage
            const double each_s = s.loading.stage_durations_s.front();
            s.loading.stage_durations_s.assign(s.loading.stress_levels.size(), each_s);
        }
        if (l.contains("stress_level_definition")) {
            const auto& d = l["stress_level_definition"];
            if (d == "q_over_qf") s.loading.stress_level_definition = protocol::StressLevelDefinition::DeviatorRatio;
            else if (d == "eq1") s.loading.stress_level_definition = protocol::StressLevelDefinition::PaperEq1;
            else throw SchemeError("/loading/stress_level_definition", "must be \"q_over_qf\" or \"eq1\"");
        }
    }
    try {
        s.validate();
    } catch (const InputError& e) {
        const EngineMessage m = engine_message(e);
        throw SchemeError(pointer_for(m.field), m.why);
    }
    return s;
}

json without_retired_fields(json j) {
    if (!j.is_object()) return j;
    if (j.contains("effects") && j["effects"].is_object()) {
        const auto& fx = j["effects"];
        if (fx.contains("rolling_resistance") && fx["rolling_resistance"] == true) {
            const json mu = fx.contains("rolling_friction") ? fx["rolling_friction"] : json(0.1);
            if (!j.contains("micro") || !j["micro"].is_object()) j["micro"] = json::object();
            j["micro"]["rolling_friction"] = mu;
        }
    }
    for (const auto& f : retired_fields())
        if (j.contains(f.section) && j[f.section].is_object()) j[f.section].erase(f.key);
    return j;
}

json scheme_to_json(const TestScheme& s0) {
    TestScheme s = s0;
    json j = json::object();
    j["name"] = s.name;
    j["seed"] = s.seed;
    j["threads"] = s.threads;
    j["max_particles"] = s.max_particles;
    for (const auto& f : number_fields()) j[f.section][f.key] = f.ref(s) / f.to_si;
    for (const auto& f : bool_fields()) j[f.section][f.key] = f.ref(s);
    j["specimen"]["lateral_boundary"] =
        s.specimen.lateral_boundary == protocol::SpecimenSpec::LateralBoundary::GrainPressure ? "grain_pressure" : "bonded_membrane";
    j["gradation"]["kind"] = s.gradation.kind == protocol::GradationSpec::Kind::SieveCurve ? "sieve_curve" : "radius_ratio";
    json curve = json::array();
    for (const auto& p : s.gradation.sieve_curve) curve.push_back({{"size_mm", p.size_m * 1e3}, {"passing_pct", p.passing_pct}});
    j["gradation"]["sieve_curve"] = curve;
    j["loading"]["stress_levels"] = s.loading.stress_levels;
    json d = json::array();
    for (double t : s.loading.stage_durations_s) d.push_back(t / 60.0);
    j["loading"]["stage_durations_min"] = d;
    j["loading"]["stress_level_definition"] =
        s.loading.stress_level_definition == protocol::StressLevelDefinition::PaperEq1 ? "eq1" : "q_over_qf";
    return j;
}

json presets_to_json() {
    json arr = json::array();
    for (const auto& g : protocol::paper_groups())
        arr.push_back({{"name", g.name}, {"description", g.description}, {"scheme", scheme_to_json(g.scheme)}});
    return {{"presets", arr}};
}

}  // namespace triax::io
