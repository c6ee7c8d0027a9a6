#include "engine/diagnose/final_model.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/protocol/membrane_compliance.hpp"

namespace triax::diagnose {

namespace {

const FittedParameter* find(const std::vector<FittedParameter>& ps, const std::string& name) {
    const auto it = std::find_if(ps.begin(), ps.end(), [&](const FittedParameter& p) { return p.name == name; });
    return it == ps.end() ? nullptr : &*it;
}

double value_of(const std::vector<FittedParameter>& ps, const std::string& name) {
    const FittedParameter* p = find(ps, name);
    if (!p) throw std::invalid_argument("the report has no parameter '" + name + "' of the model it names");
    return p->value;
}

}  // namespace

ModelPoint final_model_point(const ForwardModel& model, const DiagnosisReport& report) {
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

void apply_fitted_artefacts(protocol::TestScheme& s, const std::vector<FittedParameter>& parameters) {
    if (const FittedParameter* p = find(parameters, "seating_strain"); p && p->value > 0.0) {
        s.effects.seating_error = true;
        s.effects.seating_displacement_m = p->value * s.specimen.height_m;
    }
    if (const FittedParameter* p = find(parameters, "membrane_stiffness"); p && p->value > 0.0) {
        if (!(s.effects.membrane_thickness_m > 0.0))
            throw std::invalid_argument("membrane compliance needs a membrane thickness > 0 in the scheme");
        s.effects.membrane_compliance = true;
        s.effects.membrane_modulus_pa =
            protocol::membrane_modulus_for_stiffness_pa(p->value, s.effects.membrane_thickness_m, s.specimen.diameter_m);
    }
}

}  // namespace triax::diagnose
