// Strength envelope in lab units (see strength_envelope_json.hpp).
#include "server/io/strength_envelope_json.hpp"

#include <cmath>

#include "engine/diagnose/lab_macro.hpp"

namespace triax::io {

using nlohmann::json;

PqLine mohr_coulomb_pq_line(double friction_angle_deg, double cohesion_kpa) {
    const double phi = friction_angle_deg * 3.14159265358979323846 / 180.0;
    const double s = std::sin(phi);
    return {6.0 * s / (3.0 - s), 6.0 * cohesion_kpa * std::cos(phi) / (3.0 - s)};
}

json strength_envelope_json(const diagnose::LabDataset& curves) {
    const auto macro = diagnose::lab_macro(curves);
    json circles = json::array();
    for (const auto& s : macro.shear) {
        const double sigma3 = s.confining_pa * 1e-3, q = s.q_peak_pa * 1e-3;
        circles.push_back({{"sigma3_kPa", sigma3},
                           {"sigma1_kPa", sigma3 + q},
                           {"q_peak_kPa", q},
                           {"p_kPa", sigma3 + q / 3.0},
                           {"axial_strain_at_peak_pct", s.strain_at_peak * 100.0}});
    }
    if (circles.empty())
        return {{"circles", circles}, {"friction_angle_deg", nullptr}, {"cohesion_kPa", nullptr},
                {"n_pressures", 0}, {"p_q_line", nullptr}};
    const double c = macro.peak_cohesion_pa * 1e-3;
    const auto line = mohr_coulomb_pq_line(macro.peak_friction_angle_deg, c);
    return {{"circles", circles},
            {"friction_angle_deg", macro.peak_friction_angle_deg},
            {"cohesion_kPa", c},
            {"n_pressures", circles.size()},
            {"p_q_line", {{"slope", line.slope}, {"intercept_kPa", line.intercept_kpa}}}};
}

}  // namespace triax::io
