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
// 2. Asperity wear (slip weakening): the creep slip grinds the contact's asperities,
//      D <- D_max - (D_max - D) exp(-delta / s_w),
//    and the Coulomb limit drops to mu (1 - D) Fn (engine: ContactStore::asperity_wear).
//    Wear raises f, which opens capacity and speeds the slip: a feedback whose gain grows
//    with the share of contacts near sliding.
// 3. Stress corrosion of contact bonds (Potyondy 2007):
//      dDb/dt = b1 exp(b2 rho)  when rho > rho_th,   rho = max(tension / Tn, |Fs| / Ss)
//    the engine scales bond strengths by (1 - Db).
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
#include "engine/creep/rate_process_params.hpp"

namespace triax::creep {

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
    // Acts on the contacts between particles of group soil_group.
    explicit RateProcessCreep(const RateProcessParams& p, int soil_group = 0);

    // Ages every soil contact at its present load: its creep slip becomes the equilibrium
    // slip of its present mobilisation plus the aging margin (contact aging, Dieterich
    // 1972: a contact held at rest gains static strength), so it creeps again only when
    // a later load raises its mobilisation beyond that.
    void age(World& world) const;

    // What advance() would do over dt, without changing the world.
    CreepUpdateSummary trial(const World& world, double dt_s) const;

    // Updates slip, wear, shear forces and bond corrosion over dt (s); books the
    // dissipation in world.energy().creep.
    CreepUpdateSummary advance(World& world, double dt_s) const;

    double equilibrium_slip(double mobilisation) const {
        return p_.slip_hardening_length_m * mobilisation / (1.0 - mobilisation + p_.capacity_offset);
    }

private:
    // One pass over the contacts; writes the world only when kApply (a trial reads it).
    template <bool kApply>
    CreepUpdateSummary update(std::conditional_t<kApply, World&, const World&> world, double dt_s) const;
    RateProcessParams p_;
    int soil_group_;
};

}  // namespace triax::creep
