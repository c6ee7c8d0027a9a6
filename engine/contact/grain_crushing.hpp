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
// Softening (h < 0, an option; docs/creep.md "Crushing that softens"): the yield force
// falls as the grain crushes, F_y = max(rho F_c, F_c + h kn delta_p), down to a residual
// rho F_c: the split grain's fragments no longer bridge the gap and the contact sheds its
// load to its neighbours (the load path goes with the grain). On the falling branch the
// same return map holds (1 + h > 0); past the residual it is perfectly plastic at rho F_c.
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

#include <Eigen/Eigenvalues>

#include "engine/contact/contact_store.hpp"
#include "engine/core/particle_arrays.hpp"

namespace triax {

// The grains' strengths; the contact law's h, rho and friction loss are crush_contacts' arguments.
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
// accumulated delta_p, crushing force F_c, normal stiffness kn, hardening ratio h (> -1),
// residual ratio rho (used when h < 0).
inline CrushStep crush_return_map(double delta_e, double delta_p, double f_c, double kn, double h,
                                  double residual_ratio = 0.0) {
    CrushStep s;
    const double f_el = kn * delta_e;
    const double f_res = residual_ratio * f_c;
    const double f_y = std::max(f_res, f_c + h * kn * delta_p);
    if (delta_e <= 0.0 || f_el <= f_y) return s;
    s.plastic_increment = (f_el - f_y) / ((1.0 + h) * kn);
    // Softening that runs past the residual: the rest of the step is perfectly plastic.
    if (h < 0.0 && f_c + h * kn * (delta_p + s.plastic_increment) < f_res) s.plastic_increment = (f_el - f_res) / kn;
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
// friction_loss: a crushed contact's friction drops to mu (1 - friction_loss) (the
// comminuted fragments at the contact roll and lose their interlocking); it is stored as
// the contact's asperity wear, so it lasts as long as the contact. 0 = friction kept.
// breaks_bond: a bonded contact that crushes loses its bond. The cement or suction bridge
// sits on the asperities that crush; the comminuted zone left behind is not cemented, so
// the contact holds shear by friction only from then on. Without it, crushing caps a
// bonded contact's normal force while its cohesion stays, and a skeleton whose bonds
// corrode under creep load hands their load to grains that yield and compact instead of
// to the next bonds (docs/creep.md, "Crushing that breaks the bond").
inline CrushSummary crush_contacts(ContactStore& c, const ParticleArrays& pa, int n_grains,
                                   const std::vector<double>& crush_force, double kn, double h,
                                   double friction_loss = 0.0, double residual_ratio = 0.0, bool breaks_bond = false) {
    CrushSummary sum;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const int i = c.i[k], j = c.j[k];
        if (i >= n_grains || j >= n_grains) continue;
        const double dist = (pa.position[j] - pa.position[i]).norm();
        const double delta_p = c.creep_normal_offset[k];
        const double delta_e = pa.radius[i] + pa.radius[j] - dist + c.reference_gap[k] - delta_p;
        const CrushStep s = crush_return_map(delta_e, delta_p, std::min(crush_force[i], crush_force[j]), kn, h, residual_ratio);
        if (s.plastic_increment <= 0.0) continue;
        c.creep_normal_offset[k] = delta_p + s.plastic_increment;
        c.normal_force[k] -= kn * s.plastic_increment;
        if (friction_loss > 0.0) c.asperity_wear[k] = std::max(c.asperity_wear[k], friction_loss);
        if (breaks_bond && c.bonded[k]) {
            c.bonded[k] = 0;
            ++sum.bonds_broken;
        }
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
//
// Options (session 7, docs/creep.md "Load-dependent fatigue drive"; all off by default):
// - drive: what r measures. CappedPeakForce is the law above. PeakForce is F_max / F_c
//   uncapped. GrainStress is the grain's splitting drive from its whole force set: the
//   average stress tensor sigma = (1/V) sum_c x_c (x) f_c over all its contacts (grains,
//   membrane, platens), and r = F_eq / F_c with the equivalent diametral force
//   F_eq = (pi d^2 / 6)(sigma_1 - sigma_3) (V = pi d^3 / 6). A grain squeezed by
//   two opposite forces F has F_eq = F (the Weibull strength's F/d^2 convention); a grain
//   loaded equally from all sides has F_eq = 0: the tensile stress that splits a grain
//   comes from the deviatoric part of its loading, and contacts around it confine it
//   (the coordination effect of McDowell & Bolton 1998; Jaeger's F/d^2 is the
//   two-contact case). Uncapped: the drive of a grain at yield rises with the stage load.
// - instant_life_s: a grain whose life at the present forces is shorter than this fails
//   at once (instantaneous crushing, part of the response to the load it just received),
//   not in a time step that the increment schedule would have to resolve.
// - life scale per grain (strength spread): the brittle lifetime law
//   t_f = B S^(n-2) sigma^-n gives, at a fixed ratio r = sigma / S, t_f = B r^-n S^-2,
//   i.e. t0_i = t0 (S_i / S_ref)^-2 with S_i the grain's Weibull strength F_c,i / d_i^2.
constexpr double kFatigueDamageMax = 0.9;

enum class FatigueDrive { CappedPeakForce, PeakForce, GrainStress };

struct GrainFatigueParams {
    double time_s = 0.0;     // t0: failure time of a grain loaded to its strength x (n + 1); 0 = off
    double exponent = 20.0;  // n: static-fatigue (Charles) exponent
    double ratio_cap = 1.0;  // r is capped here (1: beyond the strength = at it); CappedPeakForce only
    FatigueDrive drive = FatigueDrive::CappedPeakForce;
    double instant_life_s = 0.0;   // lives shorter than this end at once (0 = off)
    bool strength_spread = false;  // t0_i = t0 (S_i / S_ref)^-2 (Specimen's life scale)
    bool enabled() const { return time_s > 0.0; }
    double drive_ratio(double r) const { return drive == FatigueDrive::CappedPeakForce ? std::min(r, ratio_cap) : r; }
};

// Life scale t0_i / t0 of a grain of Weibull strength S_i (Pa): (S_i / S_ref)^-2, from the
// brittle lifetime law (above). At a fixed stress sigma its life then goes as
// S_i^-2 (sigma / S_i)^-n = S_i^(n-2) sigma^-n: the stronger grain lives longer.
inline double fatigue_life_scale(double strength_pa, double reference_pa) {
    return std::pow(strength_pa / reference_pa, -2.0);
}

// Damage after dt at fixed force ratio r (exact, see above); life_scale multiplies t0.
inline double fatigue_damage_update(double damage, double r, double dt, const GrainFatigueParams& p,
                                    double life_scale = 1.0) {
    if (!p.enabled() || r <= 0.0 || dt <= 0.0) return damage;
    const double n = p.exponent;
    const double rate = (n + 1.0) * (dt / (p.time_s * life_scale)) * std::pow(p.drive_ratio(r), n);
    const double rest = std::pow(1.0 - damage, n + 1.0) - rate;
    if (rest <= 0.0) return kFatigueDamageMax;
    return std::min(kFatigueDamageMax, 1.0 - std::pow(rest, 1.0 / (n + 1.0)));
}

// Time (s) for a grain at fixed force ratio r to reach D_max from damage D (the exact
// update's inverse): t = t0 ((1 - D)^(n+1) - (1 - D_max)^(n+1)) / ((n + 1) r^n).
// Infinite when r <= 0 or the fatigue is off; 0 for a grain already at D_max.
inline double fatigue_time_to_failure(double damage, double r, const GrainFatigueParams& p, double life_scale = 1.0) {
    if (!p.enabled() || r <= 0.0) return HUGE_VAL;
    if (damage >= kFatigueDamageMax) return 0.0;
    const double n = p.exponent;
    const double span = std::pow(1.0 - damage, n + 1.0) - std::pow(1.0 - kFatigueDamageMax, n + 1.0);
    return (p.time_s * life_scale) * span / ((n + 1.0) * std::pow(p.drive_ratio(r), n));
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

// Grain i's splitting drive as an equivalent diametral force (N): F_eq = (S_1 - S_3) / d,
// S = sum_c (x_c - x_i) (x) f_c (compression positive) over all of the grain's contacts
// (the average stress tensor times V = pi d^3 / 6, so F_eq = (pi d^2 / 6)(sigma_1 - sigma_3)).
// Ball-ball contacts: branch r_i n, force on the far ball force_on_j (the same form for both
// balls); wall contacts: branch contact point - centre, force on the particle.
inline void grain_stress_drive_forces(const ContactStore& c, const WallContactStore* walls, const ParticleArrays& pa,
                                      int n_grains, std::vector<double>& f_eq) {
    std::vector<Mat3> s(static_cast<std::size_t>(n_grains), Mat3::Zero());
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.active[k]) continue;
        const int i = c.i[k], j = c.j[k];
        if (i >= n_grains && j >= n_grains) continue;
        const Vec3 d = pa.position[j] - pa.position[i];
        const double len = d.norm();
        if (len <= 0.0) continue;
        const Vec3 n = d / len;
        const Mat3 nf = n * c.force_on_j[k].transpose();
        if (i < n_grains) s[i] += pa.radius[i] * nf;
        if (j < n_grains) s[j] += pa.radius[j] * nf;
    }
    if (walls != nullptr)
        for (std::size_t k = 0; k < walls->size(); ++k) {
            if (!walls->active[k]) continue;
            const int i = walls->particle[k];
            if (i < 0 || i >= n_grains) continue;
            s[i] -= (walls->contact_point[k] - pa.position[i]) * walls->force_on_particle[k].transpose();
        }
    f_eq.assign(static_cast<std::size_t>(n_grains), 0.0);
    for (int i = 0; i < n_grains; ++i) {
        const Mat3 sym = 0.5 * (s[i] + s[i].transpose());
        const Vec3 ev = Eigen::SelfAdjointEigenSolver<Mat3>(sym, Eigen::EigenvaluesOnly).eigenvalues();  // ascending
        f_eq[i] = std::max(0.0, ev[2] - ev[0]) / (2.0 * pa.radius[i]);
    }
}

// Each grain's drive ratio r (before the CappedPeakForce cap): its peak grain-grain contact
// force, or its stress drive (GrainStress, needs the particles), over its intact F_c.
inline void grain_drive_ratios(const ContactStore& c, const WallContactStore* walls, const ParticleArrays* pa,
                               int n_grains, const std::vector<double>& crush_force, FatigueDrive drive,
                               std::vector<double>& ratio) {
    if (drive == FatigueDrive::GrainStress && pa != nullptr) grain_stress_drive_forces(c, walls, *pa, n_grains, ratio);
    else grain_peak_forces(c, n_grains, ratio);
    for (int i = 0; i < n_grains; ++i) ratio[i] /= crush_force[i];
}

struct FatigueSummary {
    double max_increment = 0.0;  // largest growth of D over the grains that do not fail in dt
    long grains_damaged = 0;     // grains whose D grew
    long grains_at_strength = 0; // grains with r >= 1 (a contact at or above the intact strength)
    long grains_failed = 0;      // grains at D_max after the update
    double max_ratio = 0.0;      // largest r (uncapped) over the grains not failed
    // Shortest time (s) for a grain not yet at D_max to reach it at the present forces:
    // the next failure event, where the load must be redistributed before going on.
    double next_failure_s = HUGE_VAL;
};

// Advances every grain's fatigue damage over dt at its drive ratio ratio[i] (life scale
// life_scale[i], or 1 when null) and writes the effective crushing forces F_c (1 - D) that
// the return map then uses. With apply = false it only reports (a dry run for the
// increment splitting).
inline FatigueSummary fatigue_grains(const std::vector<double>& ratio, const std::vector<double>* life_scale,
                                     const std::vector<double>& crush_force, std::vector<double>& damage,
                                     std::vector<double>& effective_force, double dt, const GrainFatigueParams& p,
                                     bool apply = true) {
    FatigueSummary sum;
    if (!p.enabled() || crush_force.empty()) return sum;
    const int n_grains = static_cast<int>(ratio.size());
    for (int i = 0; i < n_grains; ++i) {
        const double r = ratio[i];
        const double ls = life_scale != nullptr ? (*life_scale)[i] : 1.0;
        if (damage[i] < kFatigueDamageMax) {
            sum.max_ratio = std::max(sum.max_ratio, r);
            sum.next_failure_s = std::min(sum.next_failure_s, fatigue_time_to_failure(damage[i], r, p, ls));
        }
        const double d_new = fatigue_damage_update(damage[i], r, dt, p, ls);
        const double inc = d_new - damage[i];
        if (r >= 1.0) ++sum.grains_at_strength;
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

// The session-5 form: drive by the grains' peak grain-grain contact forces.
inline FatigueSummary fatigue_grains(const ContactStore& c, int n_grains, const std::vector<double>& crush_force,
                                     std::vector<double>& damage, std::vector<double>& effective_force, double dt,
                                     const GrainFatigueParams& p, bool apply = true) {
    if (!p.enabled() || crush_force.empty()) return {};
    std::vector<double> ratio;
    grain_drive_ratios(c, nullptr, nullptr, n_grains, crush_force, FatigueDrive::CappedPeakForce, ratio);
    return fatigue_grains(ratio, nullptr, crush_force, damage, effective_force, dt, p, apply);
}

// Instantaneous crushing: every grain not yet failed whose life at its present drive is
// shorter than p.instant_life_s goes to D_max now (no time passes). Returns how many; the
// caller relaxes the specimen (load passed on) and calls again while any fail.
inline long fail_short_lived_grains(const std::vector<double>& ratio, const std::vector<double>* life_scale,
                                    const std::vector<double>& crush_force, std::vector<double>& damage,
                                    std::vector<double>& effective_force, const GrainFatigueParams& p) {
    if (!p.enabled() || p.instant_life_s <= 0.0 || crush_force.empty()) return 0;
    long failed = 0;
    for (std::size_t i = 0; i < ratio.size(); ++i) {
        if (damage[i] >= kFatigueDamageMax) continue;
        const double ls = life_scale != nullptr ? (*life_scale)[i] : 1.0;
        if (fatigue_time_to_failure(damage[i], ratio[i], p, ls) >= p.instant_life_s) continue;
        damage[i] = kFatigueDamageMax;
        effective_force[i] = crush_force[i] * (1.0 - kFatigueDamageMax);
        ++failed;
    }
    return failed;
}

}  // namespace triax
