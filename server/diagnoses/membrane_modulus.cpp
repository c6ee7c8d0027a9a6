#include "server/diagnoses/membrane_modulus.hpp"

#include "engine/protocol/membrane_compliance.hpp"

namespace triax::service {

using nlohmann::json;

void add_membrane_modulus(json& parameters, const protocol::TestScheme& scheme) {
    const double t = scheme.effects.membrane_thickness_m, d = scheme.specimen.diameter_m;
    if (!parameters.is_array() || !(t > 0.0)) return;
    const auto kpa = [&](double km) { return 1e-3 * protocol::membrane_modulus_for_stiffness_pa(km, t, d); };
    for (auto& p : parameters) {
        if (!p.is_object() || p.value("name", std::string()) != "membrane_stiffness" || !p.contains("value")) continue;
        p["scheme_field"] = "/effects/membrane_modulus_kPa";
        p["scheme_value"] = kpa(p["value"].get<double>());
        p["scheme_std"] = kpa(p.value("std", 0.0));
    }
}

void add_membrane_modulus_to_report(json& report, const protocol::TestScheme& scheme) {
    if (!report.is_object()) return;
    for (const char* list : {"parameters", "base_parameters"})
        if (report.contains(list)) add_membrane_modulus(report[list], scheme);
    if (report.contains("candidates") && report["candidates"].is_array())
        for (auto& c : report["candidates"])
            if (c.is_object() && c.contains("parameters")) add_membrane_modulus(c["parameters"], scheme);
}

}  // namespace triax::service
