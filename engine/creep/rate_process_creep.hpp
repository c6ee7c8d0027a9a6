#pragma once
// Time-dependent contact mechanism (docs/creep.md), applied between mechanical
// relaxations over a physical-time increment dt. Per soil-soil contact with compressive
// normal force Fn, shear force Fs and friction mu (1 - D):
//
// 1. Delayed slip (a Kelvin element in rate-process form, Kuhn & Mitchell 1993):
//      ds/dt = A sinh(beta f) (1 - s / s_eq(f)),   f = |Fs| / (mu (1 - D) Fn) in [0, 1]
//      s_eq(f) = s_h f / (1 - f + eps)
//    s is the contact's accumulated creep slip. The contact creeps towards the slip its
//    mobilisation can sustain and stops there: creep decelerates and converges; a higher
//    stage load raises f and opens new capacity; near sliding (f -> 1) the capacity is
//    large. The update is the exact solution at fixed f over dt (unconditionally stable):
//      s <- s_eq - (s_eq - s) exp(-A sinh(beta f) dt / s_eq)
//    and the slip relaxes the shear spring, Fs <- Fs (1 - ks delta / |Fs|).
//    Secondary flow (the Maxwell dashpot of a Burgers contact, with a Bingham threshold):
//    a contact at f >= f_c (critical mobilisation) slips steadily, without a capacity,
//      ds/dt = A_f sinh(beta f)     until the relaxed spring brings f down to f_c.
//    Asperity wear (below) raises f again, so a worn contact keeps flowing: the steady
//    strength of a contact at creep rates is f_c mu (1 - D) Fn, lower than the fast one.
//    Flow slip wears over its own length s_wf; an aged contact flows only above its aged
//    threshold f_th = f + m_age (ContactStore::flow_threshold), and flowing erases it.
//    Off by default (f_c > 1): docs/creep.md says what it gave on the CI specimen.
// 2. Asperity wear (slip weakening): the creep slip grinds the contact's asperities,
//      D <- D_max - (D_max - D) exp(-delta / s_w),
//    and the Coulomb limit drops to mu (1 - D) Fn (engine: ContactStore::asperity_wear).
//    Wear raises f, which opens capacity and speeds the slip: a feedback whose gain grows
//    with the share of contacts near sliding.
//    Slow-slip weakening: Coulomb sliding in a creep hold's relaxations happens at creep
//    rates, where the friction of velocity-strengthening gouge is lower by
//    (a - b) ln(v_test / v_creep) (rate-and-state steady state); the state evolves over the
//    slip, so that sliding wears the contact towards that lower friction,
//      D <- max(D, D_s - (D_s - D) exp(-sliding / d_c)),
//    D_s = slow_slip_wear_max, d_c = slow_slip_wear_length_m (off at D_s = 0). Only the
//    sliding after a stage's loading step counts (forget_sliding()).
// 3. Stress corrosion of contact bonds (Potyondy 2007):
//      dDb/dt = b1 exp(b2 rho)  when rho > rho_th,   rho = max(tension / Tn, |Fs| / Ss)
//    the engine scales bond strengths by (1 - Db).
//    A bond that broke after corroding (Db > 0, no longer bonded) leaves its weathered
//    cement as clay gouge in the contact: its friction drops to mu (1 - D_g),
//    D_g = corroded_bond_friction_loss (off at 0), applied at the next update.
//
// A consolidated specimen is aged (age()): every contact already carries the delayed slip
// its consolidation load sustains, as after the lab's consolidation hold, so a stage's
// creep comes from the mobilisation it adds. The DEM cycles after each update carry no
// physical time: the clock advances by dt only (quasi-static mapping).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "engine/core/world.hpp"

namespace triax::creep {

struct RateProcessParams {
    double slip_rate_a_m_s = 0.0;         // A
    double slip_beta = 6.0;               // beta
    double slip_capacity_m = 10.0e-6;     // s_h
    double capacity_offset = 0.05;        // eps: capacity at sliding = s_h / eps
    double aging_margin = 0.0;            // rise of mobilisation an aged contact bears without creep
    double critical_mobilisation = 2.0;   // f_c: steady (secondary) flow at f >= f_c; > 1 = off
    double flow_rate_scale = 1.0;         // A_f / A: the flow's rate factor relative to the delayed slip's
    double wear_length_m = 0.0;           // s_w, 0 = no wear
    double flow_wear_length_m = 0.0;      // s_wf, wear length of flow slip; 0 = s_w
    double slow_slip_wear_max = 0.0;      // D_s: friction loss of a contact sliding at creep rates; 0 = off
    double slow_slip_wear_length_m = 20.0e-6;  // d_c: the sliding over which it sets in
    double wear_max = 0.0;                // D_max
    double bond_corrosion_b1_per_s = 0.0; // b1
    double bond_corrosion_b2 = 10.0;      // b2
    double bond_corrosion_threshold = 0.9;
    double corroded_bond_friction_loss = 0.0;  // D_g: friction loss where a corroded bond broke; 0 = off
    int soil_group = 0;
};

struct CreepUpdateSummary {
    double dissipated_j = 0.0;         // spring energy relaxed by delayed slip
    double max_slip_m = 0.0;           // largest slip of the increment
    double relaxation = 0.0;           // sum ks delta / sum |Fs|: share of shear force relaxed
    double mean_damage = 0.0;          // over bonded contacts
    double mean_asperity_wear = 0.0;   // over frictional soil contacts
    long bonds_damaged = 0;            // bonds whose corrosion grew
};

class RateProcessCreep {
public:
    explicit RateProcessCreep(const RateProcessParams& p);

    // Ages every soil contact at its present load: its creep slip becomes the equilibrium
    // slip of its present mobilisation plus the aging margin (contact aging, Dieterich
    // 1972: a contact held at rest gains static strength), so it creeps again only when
    // a later load raises its mobilisation beyond that.
    void age(World& world) const;

    // Drops the Coulomb sliding the contacts have accumulated so far (a stage's loading
    // step slides at the test's rate, not at creep rates).
    void forget_sliding(World& world) const;

    // What advance() would do over dt, without changing the world.
    CreepUpdateSummary trial(const World& world, double dt_s) const;

    // Updates slip, wear, shear forces and bond corrosion over dt (s); books the
    // dissipation in world.energy().creep.
    CreepUpdateSummary advance(World& world, double dt_s) const;

    double equilibrium_slip(double mobilisation) const {
        return p_.slip_capacity_m * mobilisation / (1.0 - mobilisation + p_.capacity_offset);
    }

    // Secondary flow of a contact at mobilisation f >= f_c over dt: the steady slip
    // A_f sinh(beta f) dt, stopped where the relaxed spring brings f down to f_c, i.e. at
    // (|Fs| - f_c |Fs| / f) / ks (|Fs| / f = mu (1 - D) Fn is the contact's Coulomb limit).
    double flow_slip(double f, double fs, double ks, double dt) const {
        if (!(f >= p_.critical_mobilisation) || !(f > 0.0) || !(ks > 0.0)) return 0.0;
        const double to_fc = fs * (1.0 - p_.critical_mobilisation / f) / ks;
        return std::min(p_.flow_rate_scale * p_.slip_rate_a_m_s * std::sinh(p_.slip_beta * f) * dt, to_fc);
    }

private:
    // One pass over the contacts; writes the world only when kApply (a trial reads it).
    template <bool kApply>
    CreepUpdateSummary update(std::conditional_t<kApply, World&, const World&> world, double dt_s) const;
    RateProcessParams p_;
};

}  // namespace triax::creep
