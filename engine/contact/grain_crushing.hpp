#pragma once
// Crushable grain contacts: local crushing (asperity and edge breakage, comminution at
// the contact) of grains whose strength falls with size (Weibull; McDowell & Bolton 1998,
// Geotechnique 48(5); Russell & Khalili's crushing contacts; docs/protocol.md, finding 2).
//
// Strength of a grain of diameter d (Weibull weakest link, survival
// P_s = exp(-(d/d0)^3 (sigma/sigma0)^m)): a grain drawn with survival quantile u in (0, 1)
// crushes at
//     sigma_c = sigma0 (d/d0)^(-3/m) (-ln u)^(1/m),   F_c = sigma_c d^2
// (the characteristic tensile stress of a diametrically loaded grain is F/d^2). A contact
// crushes at the force of its weaker grain.
//
// Normal law of a crushable contact (elastic - plastic with linear hardening): the
// elastic force kn (delta - delta_p) may not exceed the yield force
//     F_y(delta_p) = F_c + h kn delta_p
// (h = hardening ratio: the crushed zone widens and the contact area grows as the
// grains flatten). Beyond it the overlap grows plastically: the spring's zero moves by
// delta_p (the crushed volume is lost, i.e. contraction of the skeleton); unloading is
// elastic from the shifted zero. The return map is exact for this bilinear law:
//     d(delta_p) = (kn delta_e - F_y) / ((1 + h) kn)     when kn delta_e > F_y.
// The spring energy it releases, 0.5 kn (delta_e^2 - (delta_e - d(delta_p))^2), is the
// breakage energy (EnergyLedger::breakage): the work that went into new fracture surface
// and fragment rearrangement, dissipated, not stored.
//
// The engine's contact loop already shifts each ball-ball contact's spring zero by
// ContactStore::creep_normal_offset (kept while the grains overlap, reset when they
// separate), so delta_p lives there and crush_contacts() applies the return map between
// force cycles (a few steps' lag at quasi-static rates).
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/contact/contact_store.hpp"
#include "engine/core/particle_arrays.hpp"

namespace triax {

struct GrainCrushingParams {
    double strength_pa = 0.0;          // sigma0: characteristic strength at d0 (0 = off)
    double reference_diameter_m = 0.01; // d0
    double weibull_modulus = 5.0;      // m: spread of strengths and size effect (-3/m)
    double hardening_ratio = 0.02;     // h: post-crushing stiffness ratio (tangent h/(1+h) kn)
    bool enabled() const { return strength_pa > 0.0; }
};

// Crushing strength (Pa) of a grain of diameter d with survival quantile u in (0, 1).
inline double grain_crushing_strength(const GrainCrushingParams& p, double d, double u) {
    const double m = p.weibull_modulus;
    return p.strength_pa * std::pow(d / p.reference_diameter_m, -3.0 / m) * std::pow(-std::log(u), 1.0 / m);
}

// Crushing force (N) of that grain: F_c = sigma_c d^2.
inline double grain_crushing_force(const GrainCrushingParams& p, double d, double u) {
    return grain_crushing_strength(p, d, u) * d * d;
}

struct CrushStep {
    double plastic_increment = 0.0;  // m, added to delta_p
    double dissipated = 0.0;         // J
};

// Return map of one contact: elastic overlap delta_e (m, after the current delta_p),
// accumulated delta_p, crushing force F_c, normal stiffness kn, hardening ratio h.
inline CrushStep crush_return_map(double delta_e, double delta_p, double f_c, double kn, double h) {
    CrushStep s;
    const double f_el = kn * delta_e;
    const double f_y = f_c + h * kn * delta_p;
    if (delta_e <= 0.0 || f_el <= f_y) return s;
    s.plastic_increment = (f_el - f_y) / ((1.0 + h) * kn);
    const double after = delta_e - s.plastic_increment;
    s.dissipated = 0.5 * kn * (delta_e * delta_e - after * after);
    return s;
}

struct CrushSummary {
    long crushing = 0;          // contacts that crushed in this pass
    double dissipated_j = 0.0;  // breakage energy of the pass
};

// One pass over the ball-ball contacts between grains [0, n_grains): each contact whose
// elastic force exceeds its yield force crushes (return map above). crush_force[i] is
// grain i's F_c; kn the grains' normal stiffness. Serial, in slot order (deterministic).
inline CrushSummary crush_contacts(ContactStore& c, const ParticleArrays& pa, int n_grains,
                                   const std::vector<double>& crush_force, double kn, double h) {
    CrushSummary sum;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const int i = c.i[k], j = c.j[k];
        if (i >= n_grains || j >= n_grains) continue;
        const double dist = (pa.position[j] - pa.position[i]).norm();
        const double delta_p = c.creep_normal_offset[k];
        const double delta_e = pa.radius[i] + pa.radius[j] - dist + c.reference_gap[k] - delta_p;
        const CrushStep s = crush_return_map(delta_e, delta_p, std::min(crush_force[i], crush_force[j]), kn, h);
        if (s.plastic_increment <= 0.0) continue;
        c.creep_normal_offset[k] = delta_p + s.plastic_increment;
        c.normal_force[k] -= kn * s.plastic_increment;
        ++sum.crushing;
        sum.dissipated_j += s.dissipated;
    }
    return sum;
}

// ---- Static fatigue: delayed, time-dependent crushing (creep stages only) -------------
// A grain under sustained load breaks after a time, not at once: subcritical crack growth
// (stress corrosion; Charles' law v = v0 (K/K_c)^n, n ~ 10-40 for rock) lets a crack grow
// at K < K_c until it reaches the critical length (Oldecop & Alonso 2007, Geotechnique
// 57(3): delayed breakage is how rockfill creeps; McDowell & Khan 2003, Granular Matter 5:
// DEM agglomerates with time-dependent strength). Per grain a fatigue damage D in [0, D_max]
// lowers the crushing force to F_c (1 - D), and
//     dD/dt = (1/t0) (r / (1 - D))^n,      r = min(1, F_max / F_c)
// (F_max the grain's largest grain-grain contact force, F_c its intact crushing force:
// the crack's K grows as F / strength). The rate runs away as D grows (finite-time
// failure): at fixed r the grain reaches D = 1 after t_f = t0 r^-n / (n + 1)
// (the static-fatigue law t_f ~ (F/F_c)^-n). Exact update over dt at fixed force:
//     (1 - D')^(n+1) = (1 - D)^(n+1) - (n + 1) (dt / t0) r^n,      D' <= D_max.
// r is capped at 1: a yielded (flattening) contact is at its grain's strength; the
// hardening term of the yield force is the larger area of the crushed zone, not a higher
// stress in the grain. D_max < 1: the fragments of a failed grain still carry load (the
// return map with the flattened contact's hardening then takes over).
constexpr double kFatigueDamageMax = 0.9;

struct GrainFatigueParams {
    double time_s = 0.0;     // t0: failure time of a grain loaded to its strength x (n + 1); 0 = off
    double exponent = 20.0;  // n: static-fatigue (Charles) exponent
    double ratio_cap = 1.0;  // r is capped here (1: beyond the strength = at it)
    bool enabled() const { return time_s > 0.0; }
};

// Damage after dt at fixed force ratio r (exact, see above).
inline double fatigue_damage_update(double damage, double r, double dt, const GrainFatigueParams& p) {
    if (!p.enabled() || r <= 0.0 || dt <= 0.0) return damage;
    const double n = p.exponent;
    const double rate = (n + 1.0) * (dt / p.time_s) * std::pow(std::min(r, p.ratio_cap), n);
    const double rest = std::pow(1.0 - damage, n + 1.0) - rate;
    if (rest <= 0.0) return kFatigueDamageMax;
    return std::min(kFatigueDamageMax, 1.0 - std::pow(rest, 1.0 / (n + 1.0)));
}

// Time (s) for a grain at fixed force ratio r to reach D_max from damage D (the exact
// update's inverse): t = t0 ((1 - D)^(n+1) - (1 - D_max)^(n+1)) / ((n + 1) r^n).
// Infinite when r <= 0 or the fatigue is off; 0 for a grain already at D_max.
inline double fatigue_time_to_failure(double damage, double r, const GrainFatigueParams& p) {
    if (!p.enabled() || r <= 0.0) return HUGE_VAL;
    if (damage >= kFatigueDamageMax) return 0.0;
    const double n = p.exponent;
    const double span = std::pow(1.0 - damage, n + 1.0) - std::pow(1.0 - kFatigueDamageMax, n + 1.0);
    return p.time_s * span / ((n + 1.0) * std::pow(std::min(r, p.ratio_cap), n));
}

// Largest grain-grain contact force (N, compression) on each grain [0, n_grains).
inline void grain_peak_forces(const ContactStore& c, int n_grains, std::vector<double>& f_max) {
    f_max.assign(static_cast<std::size_t>(n_grains), 0.0);
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const int i = c.i[k], j = c.j[k];
        if (i >= n_grains || j >= n_grains) continue;
        const double f = c.normal_force[k];
        f_max[i] = std::max(f_max[i], f);
        f_max[j] = std::max(f_max[j], f);
    }
}

struct FatigueSummary {
    double max_increment = 0.0;  // largest growth of D over the grains that do not fail in dt
    long grains_damaged = 0;     // grains whose D grew
    long grains_at_strength = 0; // grains with r >= 1 (a contact at or above the intact strength)
    long grains_failed = 0;      // grains at D_max after the update
    double max_ratio = 0.0;      // largest F_max / F_c (uncapped) over the grains not failed
    // Shortest time (s) for a grain not yet at D_max to reach it at the present forces:
    // the next failure event, where the load must be redistributed before going on.
    double next_failure_s = HUGE_VAL;
};

// Advances every grain's fatigue damage over dt at its present peak force and writes the
// effective crushing forces F_c (1 - D) that the return map then uses. With apply = false
// it only reports (a dry run for the increment splitting).
inline FatigueSummary fatigue_grains(const ContactStore& c, int n_grains, const std::vector<double>& crush_force,
                                     std::vector<double>& damage, std::vector<double>& effective_force, double dt,
                                     const GrainFatigueParams& p, bool apply = true) {
    FatigueSummary sum;
    if (!p.enabled() || crush_force.empty()) return sum;
    std::vector<double> f_max;
    grain_peak_forces(c, n_grains, f_max);
    for (int i = 0; i < n_grains; ++i) {
        const double r = f_max[i] / crush_force[i];
        if (damage[i] < kFatigueDamageMax) {
            sum.max_ratio = std::max(sum.max_ratio, r);
            sum.next_failure_s = std::min(sum.next_failure_s, fatigue_time_to_failure(damage[i], r, p));
        }
        const double d_new = fatigue_damage_update(damage[i], r, dt, p);
        const double inc = d_new - damage[i];
        if (f_max[i] >= crush_force[i]) ++sum.grains_at_strength;
        if (d_new >= kFatigueDamageMax) ++sum.grains_failed;
        if (inc <= 0.0) continue;
        // A grain that fails within dt is the piece's failure event (it ends the piece,
        // next_failure_s); its last runaway to D_max is not a step to be resolved.
        if (d_new < kFatigueDamageMax) sum.max_increment = std::max(sum.max_increment, inc);
        ++sum.grains_damaged;
        if (!apply) continue;
        damage[i] = d_new;
        effective_force[i] = crush_force[i] * (1.0 - d_new);
    }
    return sum;
}

}  // namespace triax
