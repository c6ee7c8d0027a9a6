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
// The engine's contact loop shifts each ball-ball contact's spring zero by
// ContactStore::plastic_overlap (kept while the grains overlap, reset when they
// separate), so delta_p lives there and crush_contacts() applies the return map between
// force cycles (a few steps' lag at quasi-static rates).
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/contact/contact_store.hpp"
#include "engine/core/particle_arrays.hpp"

namespace triax {

// The grains' strengths; the contact law's hardening ratio is crush_contacts' argument.
struct GrainCrushingParams {
    double strength_pa = 0.0;          // sigma0: characteristic strength at d0 (0 = off)
    double reference_diameter_m = 0.01; // d0
    double weibull_modulus = 5.0;      // m: spread of strengths and size effect (-3/m)
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
// accumulated delta_p, crushing force F_c, normal stiffness kn, hardening ratio h >= 0.
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
    long bonds_broken = 0;      // bonds of crushing contacts (breaks_bond)
};

// One pass over the ball-ball contacts between grains [0, n_grains): each contact whose
// elastic force exceeds its yield force crushes (return map above). crush_force[i] is
// grain i's F_c; kn the grains' normal stiffness. Serial, in slot order (deterministic).
// breaks_bond: a bonded contact that crushes loses its bond. The cement or suction bridge
// sits on the asperities that crush; the comminuted zone left behind is not cemented, so
// the contact holds shear by friction only from then on. Without it, crushing caps a
// bonded contact's normal force while its cohesion stays, and a skeleton whose bonds
// corrode under creep load hands their load to grains that yield and compact instead of
// to the next bonds (docs/creep.md, "Crushing that breaks the bond").
inline CrushSummary crush_contacts(ContactStore& c, const ParticleArrays& pa, int n_grains,
                                   const std::vector<double>& crush_force, double kn, double h,
                                   bool breaks_bond = false) {
    CrushSummary sum;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const int i = c.i[k], j = c.j[k];
        if (i >= n_grains || j >= n_grains) continue;
        const double dist = (pa.position[j] - pa.position[i]).norm();
        const double delta_p = c.plastic_overlap[k];
        const double delta_e = pa.radius[i] + pa.radius[j] - dist + c.reference_gap[k] - delta_p;
        const CrushStep s = crush_return_map(delta_e, delta_p, std::min(crush_force[i], crush_force[j]), kn, h);
        if (s.plastic_increment <= 0.0) continue;
        c.plastic_overlap[k] = delta_p + s.plastic_increment;
        c.normal_force[k] -= kn * s.plastic_increment;
        if (breaks_bond && c.bonded[k]) {
            c.bonded[k] = 0;
            ++sum.bonds_broken;
        }
        ++sum.crushing;
        sum.dissipated_j += s.dissipated;
    }
    return sum;
}

}  // namespace triax
