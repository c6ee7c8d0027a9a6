// Lab macro figures (see lab_macro.hpp).
#include "engine/diagnose/lab_macro.hpp"

#include <algorithm>
#include <cmath>

namespace triax::diagnose {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Least-squares Mohr-Coulomb envelope through (sigma3, sigma1) pairs: phi (deg) and c (Pa).
void envelope(const std::vector<std::pair<double, double>>& s31, double& phi_deg, double& c_pa) {
    phi_deg = c_pa = 0.0;
    if (s31.empty()) return;
    double n_phi = 0.0, b = 0.0;
    if (s31.size() == 1) {
        n_phi = s31[0].second / std::max(s31[0].first, 1.0);
    } else {
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        const double n = static_cast<double>(s31.size());
        for (const auto& [x, y] : s31) sx += x, sy += y, sxx += x * x, sxy += x * y;
        const double den = n * sxx - sx * sx;
        n_phi = den > 0.0 ? (n * sxy - sx * sy) / den : sy / std::max(sx, 1.0);
        b = (sy - n_phi * sx) / n;
        if (b < 0.0 || n_phi < 1.0) {  // no negative cohesion: refit through the origin
            n_phi = sxx > 0.0 ? sxy / sxx : 1.0;
            b = 0.0;
        }
    }
    n_phi = std::max(n_phi, 1.0);
    phi_deg = 2.0 * (std::atan(std::sqrt(n_phi)) * 180.0 / kPi - 45.0);
    c_pa = b / (2.0 * std::sqrt(n_phi));
}

}  // namespace

double creep_strain_per_decade(const std::vector<double>& time_s, const std::vector<double>& strain, double t0_s, double t1_s) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < time_s.size() && i < strain.size(); ++i) {
        if (!(time_s[i] >= t0_s && time_s[i] <= t1_s) || !std::isfinite(strain[i])) continue;
        const double x = std::log10(time_s[i]);
        n += 1; sx += x; sy += strain[i]; sxx += x * x; sxy += x * strain[i];
    }
    const double den = n * sxx - sx * sx;
    return n >= 3 && den > 0.0 ? (n * sxy - sx * sy) / den : 0.0;
}

LabMacro lab_macro(const LabDataset& lab) {
    LabMacro m;
    for (const auto& c : lab.curves)
        if (c.kind == CurveKind::Creep && c.axial_strain.size() == c.time_s.size() && !c.time_s.empty())
            m.creep.push_back({c.confining_pa, c.stage, c.stress_level, creep_strain_per_decade(c.time_s, c.axial_strain)});
    std::vector<std::pair<double, double>> peaks, lasts;
    for (const auto& c : lab.curves) {
        if (c.kind != CurveKind::Shear || c.deviator_pa.size() < 3 || c.axial_strain.size() != c.deviator_pa.size())
            continue;
        ShearMacro s;
        s.confining_pa = c.confining_pa;
        const auto peak = std::max_element(c.deviator_pa.begin(), c.deviator_pa.end()) - c.deviator_pa.begin();
        s.q_peak_pa = c.deviator_pa[static_cast<std::size_t>(peak)];
        s.strain_at_peak = c.axial_strain[static_cast<std::size_t>(peak)];
        s.q_last_pa = c.deviator_pa.back();
        s.last_strain = c.axial_strain.back();
        for (std::size_t i = 0; i < c.deviator_pa.size(); ++i)
            if (c.deviator_pa[i] >= 0.5 * s.q_peak_pa && c.axial_strain[i] > 0.0) {
                s.e50_pa = c.deviator_pa[i] / c.axial_strain[i];
                break;
            }
        if (c.volumetric_strain.size() == c.axial_strain.size())
            for (std::size_t i = 2; i < c.axial_strain.size(); ++i) {
                const double de = c.axial_strain[i] - c.axial_strain[i - 2];
                if (de > 1e-6) s.max_dilatancy_rate = std::max(s.max_dilatancy_rate, -(c.volumetric_strain[i] - c.volumetric_strain[i - 2]) / de);
            }
        m.shear.push_back(s);
        peaks.emplace_back(s.confining_pa, s.confining_pa + s.q_peak_pa);
        lasts.emplace_back(s.confining_pa, s.confining_pa + s.q_last_pa);
    }
    envelope(peaks, m.peak_friction_angle_deg, m.peak_cohesion_pa);
    envelope(lasts, m.last_friction_angle_deg, m.last_cohesion_pa);
    return m;
}

}  // namespace triax::diagnose
