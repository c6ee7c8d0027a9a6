#pragma once
// Time-dependent contact mechanism (docs/creep.md), applied between mechanical
// relaxations over a physical-time increment dt.
//
// 1. Rate-and-state friction at frictional soil contacts (Dieterich 1979, Ruina 1983;
//    aging law, b = m a). Per contact with Fn > 0 (compression), shear force Fs, friction
//    mu and state theta (s, the contact's age):
//      v = (D_c / t_r) x (t_r / theta)^m,   x = exp(-mu (1 - f) / a),   f = |Fs| / (mu Fn)
//      dtheta/dt = 1 - v theta / D_c = 1 - x (theta / t_r)^(1 - m)
//    Under a held load theta grows with time and v falls as t^-m (m = 1: slip logarithmic
//    in time, about D_c x per e-fold), a rate that rises steeply with the contact's
//    mobilisation. The slip unloads the contact's shear spring (Fs -> Fs - ks s); with
//    theta aging linearly at its start rate g over the increment the update is exact:
//      s = (a Fn / ks) ln(1 + (D_c / t_r) x I ks / (a Fn)),  I = int_0^dt (t_r / theta(t'))^m dt'
//    so it is unconditionally stable for any dt, and s <= |Fs| / ks.
// 2. State renewal by the loading step: the shear displacement a contact takes in its
//    stage's loading, |d|Fs|| / ks from the stage's start to its first update, renews its
//    state by the slip law, theta <- max(t_r, theta exp(-|d|Fs|| / (ks D_c))): a loaded
//    contact is young again and creeps again from the load step, as the lab's log-time
//    creep counts time from each load. The relaxations inside a stage move held contacts
//    elastically and do not renew them. t_r (renewed_age_s) is the youngest state; a new
//    contact has it.
// 3. Stress corrosion of contact bonds (Potyondy 2007):
//      dDb/dt = b1 exp(b2 rho)  when rho > rho_th
//    the engine scales bond strengths by (1 - Db). An intact Mohr-Coulomb bond holds its
//    contact: no rate-and-state slip while it lasts.
// The DEM cycles after each update carry no physical time: the clock advances by dt only
// (quasi-static mapping, docs/creep.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "engine/core/world.hpp"
#include "engine/creep/rate_state_params.hpp"

namespace triax::creep {

struct CreepUpdateSummary {
    double dissipated_j = 0.0;         // spring energy released by the creep slip
    double max_slip_m = 0.0;           // largest slip of the increment
    double relaxation = 0.0;           // sum ks s / sum |Fs|: share of shear force relaxed
    double mean_damage = 0.0;          // over bonded contacts
    double mean_age_s = 0.0;           // state theta over frictional soil contacts
    long bonds_damaged = 0;            // bonds whose corrosion grew
};

// creep_reference_shear of a contact whose stage's loading step has been counted: no
// renewal until the next begin_stage.
inline constexpr double kNoLoadingStep = -1.0;

class RateStateCreep {
public:
    // Acts on the contacts between particles of group soil_group.
    explicit RateStateCreep(const RateStateParams& p, int soil_group = 0);

    // Before a stage's loading: every soil contact's shear force becomes the reference its
    // renewal by the loading is measured from. A contact that never had a state gets the
    // consolidation's age (consolidated_age_s) before the first stage, when it was formed in
    // the preparation and consolidation, and the youngest (renewed_age_s) before a later one.
    void begin_stage(World& world, bool first_stage) const;

    // What advance() would do over dt, without changing the world.
    CreepUpdateSummary trial(const World& world, double dt_s) const;

    // Renews, ages and slips the frictional contacts and corrodes the bonds over dt (s);
    // books the released spring energy in world.energy().creep.
    CreepUpdateSummary advance(World& world, double dt_s) const;

    // Slip (m) of a contact over dt at state theta_s, mobilisation f, normal force fn (N),
    // friction mu and shear stiffness ks (N/m), the shear spring relaxing as it slips.
    double slip_over(double dt_s, double theta_s, double f, double fn, double mu, double ks) const;

    // dtheta/dt of the aging law at state theta_s, mobilisation f and friction mu.
    double aging_rate(double theta_s, double f, double mu) const;

private:
    // One pass over the contacts; writes the world only when kApply (a trial reads it).
    template <bool kApply>
    CreepUpdateSummary update(std::conditional_t<kApply, World&, const World&> world, double dt_s) const;
    RateStateParams p_;
    int soil_group_;
};

}  // namespace triax::creep
