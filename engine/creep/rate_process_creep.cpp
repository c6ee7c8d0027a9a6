#include "engine/creep/rate_process_creep.hpp"

#include "engine/contact/bond_shear_strength.hpp"

#include <algorithm>
#include <cmath>

namespace triax::creep {

RateProcessCreep::RateProcessCreep(const RateProcessParams& p, int soil_group) : p_(p), soil_group_(soil_group) {
    if (!(p.slip_rate_a_m_s >= 0.0)) throw InputError("creep.slip_rate_a_m_s: must be >= 0");
    if (!(p.slip_hardening_length_m > 0.0)) throw InputError("creep.slip_hardening_length_m: must be > 0");
    if (!(p.capacity_offset > 0.0)) throw InputError("creep.capacity_offset: must be > 0");
    if (!(p.wear_length_m >= 0.0)) throw InputError("creep.wear_length_m: must be >= 0");
    if (!(p.wear_max >= 0.0 && p.wear_max < 1.0)) throw InputError("creep.wear_max: must be in [0, 1)");
    if (!(p.aging_margin >= 0.0 && p.aging_margin <= 1.0)) throw InputError("creep.aging_margin: must be in [0, 1]");
}

namespace {
// Mobilised friction of a compressive frictional contact, or -1 when it has none.
double mobilisation(const ContactStore& c, const ContactLaw& law, std::size_t k) {
    const double fn = c.normal_force[k];
    const double fs = c.shear_force[k].norm();
    const double mu = law.friction * (1.0 - c.asperity_wear[k]);
    if (!(fn > 0.0) || !(mu > 0.0) || !(law.ks > 0.0)) return -1.0;
    return std::min(1.0, fs / (mu * fn));
}

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

void RateProcessCreep::age(World& world) const {
    auto& c = world.contacts();
    const auto& grp = world.particles().group;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k] || grp[c.i[k]] != soil_group_ || grp[c.j[k]] != soil_group_) continue;
        const double f = mobilisation(c, world.contact_law_of(k), k);
        if (f > 0.0) c.creep_slip[k] = std::max(c.creep_slip[k], equilibrium_slip(std::min(1.0, f + p_.aging_margin)));
    }
}

CreepUpdateSummary RateProcessCreep::trial(const World& world, double dt) const {
    return update<false>(world, dt);
}

CreepUpdateSummary RateProcessCreep::advance(World& world, double dt) const {
    auto out = update<true>(world, dt);
    world.energy().creep += out.dissipated_j;
    return out;
}

template <bool kApply>
CreepUpdateSummary RateProcessCreep::update(std::conditional_t<kApply, World&, const World&> world, double dt) const {
    if (!(dt >= 0.0)) throw InputError("creep advance: dt must be >= 0 s");
    CreepUpdateSummary out;
    auto& c = world.contacts();
    const auto& grp = world.particles().group;
    long bonded = 0, frictional = 0;
    double wear_sum = 0.0, damage_sum = 0.0, relaxed = 0.0, carried = 0.0;
    // Serial loop in slot order: deterministic, and cheap next to the relaxation cycles.
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        if (grp[c.i[k]] != soil_group_ || grp[c.j[k]] != soil_group_) continue;
        const ContactLaw& law = world.contact_law_of(k);
        const double fs = c.shear_force[k].norm();
        // A Mohr-Coulomb bond holds its contact: no slider, so no delayed slip while it
        // is intact; its time dependence is the bond's corrosion.
        const bool coulomb_bond = (law.bond_friction > 0.0 || law.bond_rolling_friction > 0.0) && c.bonded[k];
        const double f = coulomb_bond ? -1.0 : mobilisation(c, law, k);
        if (f > 0.0) {
            ++frictional;
            carried += fs;
            const double s = c.creep_slip[k];
            const double s_eq = equilibrium_slip(f);
            double delta = 0.0;
            if (p_.slip_rate_a_m_s > 0.0 && s < s_eq) {
                const double rate0 = p_.slip_rate_a_m_s * std::sinh(p_.slip_beta * f);
                delta = std::min((s_eq - s) * -std::expm1(-rate0 * dt / s_eq), fs / law.ks);
            }
            relaxed += law.ks * delta;
            // Asperity wear: the creep slip grinds the asperities (slip weakening).
            double wear = c.asperity_wear[k];
            const double s_w = p_.wear_length_m;
            if (s_w > 0.0 && delta > 0.0) wear = p_.wear_max - (p_.wear_max - wear) * std::exp(-delta / s_w);
            wear_sum += wear;
            if constexpr (kApply) {
                const double fs_new = fs - law.ks * delta;
                out.dissipated_j += 0.5 * (fs * fs - fs_new * fs_new) / law.ks;
                if (fs > 0.0) c.shear_force[k] *= fs_new / fs;
                c.creep_slip[k] = s + delta;
                c.asperity_wear[k] = wear;
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
    out.mean_asperity_wear = frictional ? wear_sum / frictional : 0.0;
    return out;
}

template CreepUpdateSummary RateProcessCreep::update<true>(World&, double) const;
template CreepUpdateSummary RateProcessCreep::update<false>(const World&, double) const;

}  // namespace triax::creep
