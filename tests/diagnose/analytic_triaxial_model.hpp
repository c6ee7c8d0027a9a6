#pragma once
// A cheap closed-form stand-in for the DEM forward model, used to test the diagnosis
// algorithm in milliseconds: drained hyperbolic stress-strain (Duncan-Chang with
// Mohr-Coulomb strength and pressure-dependent stiffness), a mobilisation-driven
// dilatancy rule for the volumetric strain, and log-time creep per stress level. Each
// catalog effect changes the curves the way its physical counterpart does in DEM (see
// docs/diagnosis.md), but through its own formula, so the base parameters cannot mimic it
// exactly: that is what the diagnosis must detect.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/diagnose/forward_model.hpp"

namespace triax::diagnose::testing {

struct AnalyticConditions {
    std::vector<double> confining_pa{50e3, 100e3, 200e3};
    std::vector<double> stress_levels{0.1, 0.4, 0.6, 0.8};
    double max_strain = 0.16;
    double creep_duration_s = 3000.0 * 60.0;
    // Bond degradation as the DEM model offers it with creep curves of a bonded specimen
    // (dem_forward_model.hpp): two parameters, both off at 0: the breakage index (shear and
    // creep) and an extra bond-damage rate that acts only in the creep holds. Its creep
    // signature here: damage accumulating over the hold speeds the creep up late in the
    // stage (t^2) and steeply with the stress level (S^4), where contact viscosity adds a
    // saturating primary part (1 - exp(-t/tau)) growing as S^2.
    bool creep_bond_damage = false;
};

class AnalyticTriaxialModel final : public ForwardModel {
public:
    explicit AnalyticTriaxialModel(AnalyticConditions c = {}) : c_(std::move(c)) {}

    std::vector<ParameterSpec> base_parameters() const override {
        return {{"young_modulus_at_100kPa", "Pa", 5e6, 200e6, 30e6, true},
                {"friction_angle", "deg", 25.0, 50.0, 35.0, false},
                {"dilatancy_angle", "deg", 0.0, 25.0, 8.0, false},
                {"creep_log_time_coefficient", "-", 1e-5, 1e-2, 5e-4, true}};
    }

    std::vector<ParameterSpec> effect_parameters(Effect e) const override {
        switch (e) {
            case Effect::RollingResistance: return {{"rolling_friction", "-", 0.0, 0.4, 0.1, false}};
            case Effect::BondDegradation:
                if (c_.creep_bond_damage)
                    return {{"breakage_index", "-", 0.0, 2.0, 0.5, false, true},
                            {"extra_bond_damage_rate", "-", 0.0, 9.0, 1.0, false, true}};
                return {{"breakage_index", "-", 0.0, 2.0, 0.5, false}};
            case Effect::ContactCreepViscosity:
                return {{"viscous_strain", "-", 0.0, 0.01, 0.002, false},
                        {"viscous_time", "s", 100.0, 1e5, 3000.0, true}};
            case Effect::MoistureBonding: return {{"bond_cohesion", "Pa", 0.0, 60e3, 15e3, false}};
            default: return {};
        }
    }

    LabDataset simulate(const ModelPoint& p, std::uint64_t) const override {
        if (p.base.size() != 4) throw std::invalid_argument("analytic model takes 4 base parameters");
        double mu_r = 0, breakage = 0, bond_damage = 0, visc_a = 0, visc_tau = 1, cohesion = 0;
        for (const auto& [e, v] : p.effects) {
            if (e == Effect::RollingResistance) mu_r = v.at(0);
            if (e == Effect::BondDegradation) breakage = v.at(0), bond_damage = v.size() > 1 ? v[1] : 0.0;
            if (e == Effect::ContactCreepViscosity) visc_a = v.at(0), visc_tau = v.at(1);
            if (e == Effect::MoistureBonding) cohesion = v.at(0);
        }
        const double E100 = p.base[0], phi = p.base[1] * M_PI / 180.0, psi = p.base[2] * M_PI / 180.0,
                     c_alpha = p.base[3];
        LabDataset out;
        out.name = "analytic";
        for (double s3 : c_.confining_pa) {
            const double rel = s3 / 100e3;
            const double E = E100 * std::sqrt(rel) * (1.0 + 0.5 * cohesion / s3 * 0.2);
            // Breakage curves the envelope: friction lost grows with confining pressure.
            const double phi_eff = phi - breakage * 0.06 * std::log1p(rel);
            const double kp = (1 + std::sin(phi_eff)) / (1 - std::sin(phi_eff));
            const double q_f = (kp - 1) * s3 + 2 * cohesion * std::sqrt(kp);
            const double q_ult = q_f / 0.9;
            auto hyper = [&](double eps) { return eps / (1.0 / E + eps / q_ult); };
            LabCurve sh;
            sh.kind = CurveKind::Shear;
            sh.confining_pa = s3;
            double ev = 0.0;
            const int steps = 320;
            for (int i = 0; i <= steps; ++i) {
                const double eps = c_.max_strain * i / steps;
                // Interlocking: a peak near 3 % strain that softens away, stronger at low sigma3.
                const double hump = (eps / 0.03) * std::exp(1.0 - eps / 0.03);
                const double q = hyper(eps) * (1.0 + 1.5 * mu_r * hump / std::sqrt(rel));
                const double m = std::min(q / q_ult, 1.0);
                if (i > 0) {
                    const double de = c_.max_strain / steps;
                    const double rate = 0.45 * (1.0 - m) - 1.6 * std::sin(psi) * std::pow(m, 4) -
                                        2.0 * mu_r * hump / std::sqrt(rel) * m + breakage * 0.15 * rel * m;
                    ev += rate * de;
                }
                sh.axial_strain.push_back(eps);
                sh.deviator_pa.push_back(q);
                sh.volumetric_strain.push_back(ev);
            }
            out.curves.push_back(std::move(sh));
            // Creep stages: instant strain from the hyperbola's increment, then log-time creep.
            double prev_eps = 0.0;
            int stage = 0;
            for (double S : c_.stress_levels) {
                const double q = S * q_f;
                const double eps_total = q / (E * (1.0 - q / q_ult));
                const double inst = eps_total - prev_eps;
                prev_eps = eps_total;
                LabCurve cr;
                cr.kind = CurveKind::Creep;
                cr.stage = ++stage;
                cr.confining_pa = s3;
                cr.stress_level = S;
                const double c_eff = c_alpha * S * (1.0 + breakage * rel * S) / (1.0 + 3.0 * mu_r);
                for (int i = 0; i <= 120; ++i) {
                    const double t = i == 0 ? 0.0 : std::pow(10.0, std::log10(c_.creep_duration_s) * i / 120.0);
                    const double tr = t / c_.creep_duration_s;
                    const double eps = inst + c_eff * std::log1p(t / 60.0) + visc_a * S * S * (1.0 - std::exp(-t / visc_tau)) +
                                       2e-3 * bond_damage * std::pow(S, 4) * tr * tr;
                    cr.time_s.push_back(t);
                    cr.axial_strain.push_back(eps);
                    cr.axial_deformation_m.push_back(eps * 0.2);
                }
                out.curves.push_back(std::move(cr));
            }
        }
        return out;
    }

private:
    AnalyticConditions c_;
};

}  // namespace triax::diagnose::testing
