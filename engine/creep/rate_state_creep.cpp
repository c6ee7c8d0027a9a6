#include "engine/creep/rate_state_creep.hpp"

#include "engine/contact/bond_shear_strength.hpp"

#include <algorithm>
#include <cmath>

namespace triax::creep {

RateStateCreep::RateStateCreep(const RateStateParams& p, int soil_group) : p_(p), soil_group_(soil_group) {
    if (!(p.direct_effect_a > 0.0)) throw InputError("creep.direct_effect_a: must be > 0");
    if (!(p.critical_slip_m >= 0.0)) throw InputError("creep.critical_slip_m: must be >= 0");
    if (!(p.renewed_age_s > 0.0)) throw InputError("creep.renewed_age_s: must be > 0");
    if (!(p.consolidated_age_s > 0.0)) throw InputError("creep.consolidated_age_s: must be > 0");
    if (!(p.state_exponent_m > 0.0 && p.state_exponent_m <= 1.0)) throw InputError("creep.state_exponent_m: must be in (0, 1]");
}

namespace {
// Utilisation of a bond's present strength: the larger of tension over the corroded
// tensile strength and shear over the corroded shear strength (bond_shear_strength.hpp:
// ss keep + mu_b Fn, less the part of mu_b above the grains' mu that the damage took;
// mu_b 0: PFC's contact bond) at damage d; with d 0 and mu_b 0 this is the plain ratio of
// the uncorroded bond.
double bond_utilisation(double fn, double fs, double tn, double ss, double mu_b, double mu, double d) {
    const double keep = std::max(1e-12, 1.0 - d);
    const double shear_strength = bond_shear_strength(ss, mu_b, mu, fn, d);
    return std::max(tn > 0.0 ? std::max(0.0, -fn) / (tn * keep) : 0.0,
                    shear_strength > 0.0 ? fs / shear_strength : 0.0);
}
}  // namespace

void RateStateCreep::begin_stage(World& world, bool first_stage) const {
    const double unaged = first_stage ? p_.consolidated_age_s : p_.renewed_age_s;
    auto& c = world.contacts();
    const auto& grp = world.particles().group;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k] || grp[c.i[k]] != soil_group_ || grp[c.j[k]] != soil_group_) continue;
        c.creep_reference_shear[k] = c.shear_force[k].norm();
        c.contact_age[k] = c.contact_age[k] > 0.0 ? std::max(c.contact_age[k], p_.renewed_age_s) : unaged;
    }
}

double RateStateCreep::aging_rate(double theta_s, double f, double mu) const {
    // 1 - v theta / D_c, with v theta / D_c = x (theta / t_r)^(1 - m).
    const double x = std::exp(-mu * (1.0 - f) / p_.direct_effect_a);
    return 1.0 - x * std::pow(theta_s / p_.renewed_age_s, 1.0 - p_.state_exponent_m);
}

double RateStateCreep::slip_over(double dt, double theta, double f, double fn, double mu, double ks) const {
    if (!(p_.critical_slip_m > 0.0) || !(dt > 0.0) || !(fn > 0.0) || !(ks > 0.0)) return 0.0;
    const double a = p_.direct_effect_a, m = p_.state_exponent_m, t_r = p_.renewed_age_s;
    const double x = std::exp(-mu * (1.0 - f) / a);
    // I = int_0^dt (t_r / theta(t'))^m dt' with theta(t') = theta + g t', g the aging rate
    // at the increment's start (0 for a contact at its steady state or beyond).
    const double g = std::max(0.0, aging_rate(theta, f, mu));
    double integral;
    if (g * dt < 1e-9 * theta) {
        integral = std::pow(t_r / theta, m) * dt;
    } else if (std::abs(1.0 - m) < 1e-9) {
        integral = t_r / g * std::log1p(g * dt / theta);
    } else {
        const double e = 1.0 - m;
        integral = std::pow(t_r, m) * (std::pow(theta + g * dt, e) - std::pow(theta, e)) / (e * g);
    }
    // ds/dt = (D_c / t_r) x exp(-ks s / (a Fn)) (t_r / theta)^m: the spring unloads as it slips.
    const double scale = a * fn / ks;  // m: the slip that lowers f by a / mu
    return scale * std::log1p(p_.critical_slip_m / t_r * x * integral / scale);
}

CreepUpdateSummary RateStateCreep::trial(const World& world, double dt) const {
    return update<false>(world, dt);
}

CreepUpdateSummary RateStateCreep::advance(World& world, double dt) const {
    auto out = update<true>(world, dt);
    world.energy().creep += out.dissipated_j;
    return out;
}

template <bool kApply>
CreepUpdateSummary RateStateCreep::update(std::conditional_t<kApply, World&, const World&> world, double dt) const {
    if (!(dt >= 0.0)) throw InputError("creep advance: dt must be >= 0 s");
    CreepUpdateSummary out;
    auto& c = world.contacts();
    const auto& grp = world.particles().group;
    long bonded = 0, frictional = 0;
    double age_sum = 0.0, damage_sum = 0.0, relaxed = 0.0, carried = 0.0;
    // Serial loop in slot order: deterministic, and cheap next to the relaxation cycles.
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        if (grp[c.i[k]] != soil_group_ || grp[c.j[k]] != soil_group_) continue;
        const ContactLaw& law = world.contact_law_of(k);
        const double fs = c.shear_force[k].norm();
        // A Mohr-Coulomb bond holds its contact: no slider, so no creep slip while it
        // is intact; its time dependence is the bond's corrosion.
        const bool coulomb_bond = (law.bond_friction > 0.0 || law.bond_rolling_friction > 0.0) && c.bonded[k];
        const double fn = c.normal_force[k];
        if (!coulomb_bond && fn > 0.0 && law.friction > 0.0 && law.ks > 0.0) {
            ++frictional;
            carried += fs;
            // Renewal by the shear displacement of the stage's loading step (slip law), at the
            // stage's first update only: the relaxations inside a stage move a held contact
            // elastically and do not renew it. A contact with no state yet is as young as a
            // renewed one.
            const double reference = c.creep_reference_shear[k];
            const double moved = reference >= 0.0 ? std::abs(fs - reference) / law.ks : 0.0;
            const double renewal = p_.critical_slip_m > 0.0 ? std::exp(-moved / p_.critical_slip_m) : 1.0;
            const double theta0 = std::max(p_.renewed_age_s, c.contact_age[k] * renewal);
            const double mu = law.friction;
            const double f = std::min(1.0, fs / (mu * fn));
            const double delta = std::min(slip_over(dt, theta0, f, fn, mu, law.ks), fs / law.ks);
            // Aging at the increment's start mobilisation, down to the steady state at most.
            const double g = aging_rate(theta0, f, mu);
            const double theta1 = std::max(p_.renewed_age_s, theta0 + dt * g);
            relaxed += law.ks * delta;
            age_sum += theta1;
            if constexpr (kApply) {
                const double fs_new = fs - law.ks * delta;
                out.dissipated_j += 0.5 * (fs * fs - fs_new * fs_new) / law.ks;
                if (fs > 0.0) c.shear_force[k] *= fs_new / fs;
                c.contact_age[k] = theta1;
                c.creep_reference_shear[k] = kNoLoadingStep;
            }
            out.max_slip_m = std::max(out.max_slip_m, delta);
        }
        if (c.bonded[k]) {
            ++bonded;
            double dmg = c.damage[k];
            if (p_.bond_corrosion_rate_b1_per_s > 0.0) {
                const double fn = c.normal_force[k];
                const double tn = c.bond_normal_strength[k], ss = c.bond_shear_strength[k];
                if (coulomb_bond) {
                    // Utilisation of the bond's present (corroded) strength, as in Potyondy's
                    // parallel-bond stress corrosion, where the bond stress rises as the bond
                    // shrinks: a loaded bond corrodes ever faster until it breaks (rho = 1,
                    // at the next DEM cycle). Integrated at fixed forces by midpoint sub-steps
                    // of at most 0.01 damage, so the result does not depend on the increment.
                    // An uncracked cement neck (bond_rolling_friction) counts with its moment
                    // over its corroded limit: the neck is part of the bond's cement, as the
                    // moment term of a parallel bond's stress in Potyondy's model. It cracks at
                    // 1 (next DEM cycle), so it is below 1 here.
                    const double mu_b = law.bond_friction;
                    const double ri = world.particles().radius[c.i[k]], rj = world.particles().radius[c.j[k]];
                    const bool neck_on = law.bond_rolling_friction > 0.0 && !c.neck_cracked[k];
                    const double r_bar = ri * rj / (ri + rj);
                    const double m = c.rolling_moment[k].norm();
                    auto utilisation = [&](double d) {
                        const double rho = bond_utilisation(fn, fs, tn, ss, mu_b, law.friction, d);
                        if (!neck_on) return rho;
                        const double limit =
                            bond_neck_moment_limit(law.rolling_friction, law.bond_rolling_friction, r_bar, fn, d);
                        return std::max(rho, limit > 0.0 ? m / limit : 0.0);
                    };
                    auto rate_at = [&](double r) { return p_.bond_corrosion_rate_b1_per_s * std::exp(p_.bond_corrosion_b2 * r); };
                    double left = dt;
                    bool grew = false;
                    while (left > 0.0 && dmg < 1.0) {
                        const double rho = utilisation(dmg);
                        if (!(rho > p_.bond_corrosion_threshold) || rho >= 1.0) break;
                        const double rate = rate_at(rho);
                        const double h = std::min(left, 0.01 / rate);
                        dmg = std::min(1.0, dmg + rate_at(utilisation(dmg + 0.5 * rate * h)) * h);
                        left -= h;
                        grew = true;
                    }
                    if (grew) {
                        ++out.bonds_damaged;
                        if constexpr (kApply) c.damage[k] = dmg;
                    }
                } else {
                    const double rho = bond_utilisation(fn, fs, tn, ss, 0.0, law.friction, 0.0);
                    if (rho > p_.bond_corrosion_threshold) {
                        dmg = std::min(1.0, dmg + p_.bond_corrosion_rate_b1_per_s * std::exp(p_.bond_corrosion_b2 * rho) * dt);
                        ++out.bonds_damaged;
                        if constexpr (kApply) c.damage[k] = dmg;
                    }
                }
            }
            damage_sum += dmg;
        }
    }
    out.relaxation = carried > 0.0 ? relaxed / carried : 0.0;
    out.mean_damage = bonded ? damage_sum / bonded : 0.0;
    out.mean_age_s = frictional ? age_sum / frictional : 0.0;
    return out;
}

template CreepUpdateSummary RateStateCreep::update<true>(World&, double) const;
template CreepUpdateSummary RateStateCreep::update<false>(const World&, double) const;

}  // namespace triax::creep
