#include "engine/creep/rate_process_creep.hpp"

#include <algorithm>
#include <cmath>

namespace triax::creep {

double RateProcessCreep::accumulated_slip(int i, int j) const {
    auto it = state_.find(key(std::min(i, j), std::max(i, j)));
    return it == state_.end() ? 0.0 : it->second.slip;
}

CreepUpdateSummary RateProcessCreep::advance(World& world, double dt) {
    if (!(dt >= 0.0)) throw InputError("creep advance: dt must be >= 0 s");
    CreepUpdateSummary out;
    auto& c = world.contacts();
    const auto& grp = world.particles().group;
    long bonded = 0, frictional = 0;
    double asperity_sum = 0.0;
    double damage_sum = 0.0;
    // Serial loop in slot order: deterministic, and cheap next to the relaxation cycles.
    for (std::size_t k = 0; k < c.i.size(); ++k) {
        if (!c.active[k]) continue;
        if (grp[c.i[k]] != p_.soil_group || grp[c.j[k]] != p_.soil_group) continue;
        const ContactLaw& law = world.contact_law_of(k);
        const double fs = c.shear_force[k].norm();
        const double fn = c.normal_force[k];
        // 1. viscous slip (frictional, compressive contacts only)
        if (p_.slip_rate_a_m_s > 0.0 && fn > 0.0 && fs > 0.0 && law.friction > 0.0 && law.ks > 0.0) {
            const double f = std::min(1.0, fs / (law.friction * fn));
            State& st = state_[key(c.i[k], c.j[k])];
            double& s = st.slip;
            if (f > p_.damage_threshold && p_.damage_rate_b1_per_s > 0.0)
                st.damage = std::min(0.95, st.damage + p_.damage_rate_b1_per_s * std::exp(p_.damage_b2 * f) * dt);
            asperity_sum += st.damage;
            ++frictional;
            const double weak = 1.0 - st.damage;
            // Delayed-slip capacity of the contact (a Kelvin element in rate-process form):
            // grows with mobilisation and without bound as f -> 1, and with damage.
            const double s_lim = p_.slip_hardening_length_m * f / ((1.0 - f + 0.05) * weak);
            const double v = p_.slip_rate_a_m_s * std::sinh(p_.slip_beta * f) * std::max(0.0, 1.0 - s / s_lim) / weak;
            const double delta = std::min(v * dt, fs / law.ks);
            const double fs_new = fs - law.ks * delta;
            out.dissipated_j += 0.5 * (fs * fs - fs_new * fs_new) / law.ks;
            c.shear_force[k] *= fs_new / fs;
            s += delta;
            out.max_slip_m = std::max(out.max_slip_m, delta);
        }
        // 2. stress corrosion of bonds
        if (c.bonded[k]) {
            ++bonded;
            if (p_.damage_rate_b1_per_s > 0.0) {
                const double tn = c.bond_normal_strength[k], ss = c.bond_shear_strength[k];
                const double rho = std::max(tn > 0.0 ? std::max(0.0, -fn) / tn : 0.0, ss > 0.0 ? fs / ss : 0.0);
                if (rho > p_.damage_threshold) {
                    const double dd = p_.damage_rate_b1_per_s * std::exp(p_.damage_b2 * rho) * dt;
                    c.damage[k] = std::min(1.0, c.damage[k] + dd);
                    ++out.bonds_damaged;
                }
            }
            damage_sum += c.damage[k];
        }
    }
    out.mean_damage = bonded ? damage_sum / bonded : 0.0;
    out.mean_asperity_damage = frictional ? asperity_sum / frictional : 0.0;
    world.energy().creep += out.dissipated_j;
    return out;
}

}  // namespace triax::creep
