// The final model's schemes from the engine's DemForwardModel (see model_schemes.hpp).
#include "server/diagnoses/model_schemes.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/diagnose/dem_forward_model.hpp"
#include "server/io/scheme_json.hpp"

namespace triax::service {

using nlohmann::json;
using namespace triax::diagnose;

namespace {

// A scheme name leaves room for the suffix within scheme_from_json's 200 bytes.
constexpr std::size_t kMaxBaseNameBytes = 150;

const FittedParameter* find(const std::vector<FittedParameter>& ps, const std::string& name) {
    const auto it = std::find_if(ps.begin(), ps.end(), [&](const FittedParameter& p) { return p.name == name; });
    return it == ps.end() ? nullptr : &*it;
}

double value_of(const std::vector<FittedParameter>& ps, const std::string& name) {
    const FittedParameter* p = find(ps, name);
    if (!p) throw std::invalid_argument("the report has no parameter '" + name + "' of the model it names");
    return p->value;
}

// The report's final model as the point DemForwardModel runs (physical part only).
ModelPoint final_point(const DemForwardModel& model, const DiagnosisReport& report) {
    ModelPoint point;
    for (const auto& spec : model.base_parameters()) point.base.push_back(value_of(report.parameters, spec.name));
    for (const auto& name : report.effects) {
        const auto e = effect_from_name(name);
        if (!e) throw std::invalid_argument("the report names an unknown effect '" + name + "'");
        if (is_test_artefact(*e)) continue;
        const auto specs = model.effect_parameters(*e);
        if (specs.empty()) throw std::invalid_argument("the model cannot represent the effect '" + name + "'");
        std::vector<double> values;
        bool off = true;
        for (const auto& spec : specs) {
            values.push_back(value_of(report.parameters, spec.name));
            off = off && spec.lower_is_off && values.back() <= spec.lower;
        }
        if (!off) point.effects.emplace_back(*e, std::move(values));
    }
    std::sort(point.effects.begin(), point.effects.end());
    return point;
}

// The test artefacts of the report, applied by the run's protocol (model_schemes.hpp).
void apply_artefacts(protocol::TestScheme& s, const std::vector<FittedParameter>& parameters) {
    if (const FittedParameter* p = find(parameters, "seating_strain"); p && p->value > 0.0) {
        s.effects.seating_error = true;
        s.effects.seating_displacement_m = p->value * s.specimen.height_m;
    }
    if (const FittedParameter* p = find(parameters, "membrane_stiffness"); p && p->value > 0.0) {
        if (!(s.effects.membrane_thickness_m > 0.0))
            throw std::invalid_argument("membrane compliance needs a membrane thickness > 0 in the scheme");
        s.effects.membrane_compliance = true;
        s.effects.membrane_modulus_pa = p->value * s.specimen.diameter_m / (4.0 * s.effects.membrane_thickness_m);
    }
}

// The base name cut at a UTF-8 character boundary, then the condition.
std::string scheme_name(const std::string& base, double confining_pa) {
    std::size_t n = std::min(base.size(), kMaxBaseNameBytes);
    while (n > 0 && n < base.size() && (static_cast<unsigned char>(base[n]) & 0xC0) == 0x80) --n;
    std::ostringstream out;
    out << base.substr(0, n) << " (calibrated, " << confining_pa * 1e-3 << " kPa)";
    return out.str();
}

}  // namespace

json model_schemes_json(const protocol::TestScheme& scheme, const LabDataset& lab, const DiagnoseOptions& options,
                        const DiagnosisReport& report) {
    // As run_diagnosis builds it (dem_forward_model.cpp), without the cancel observer.
    const DemForwardModel model(scheme, lab, options);
    json out = json::array();
    for (const auto& run : model.engine_runs(final_point(model, report))) {
        protocol::TestScheme s = run.standalone_scheme();
        apply_artefacts(s, report.parameters);
        s.seed = options.seed;
        s.name = scheme_name(scheme.name, s.loading.confining_pressure_pa);
        json doc = io::scheme_to_json(s);
        io::scheme_from_json(doc);  // what POST /runs will do with it; throws SchemeError
        out.push_back({{"confining_kPa", s.loading.confining_pressure_pa * 1e-3}, {"scheme", std::move(doc)}});
    }
    return out;
}

}  // namespace triax::service
