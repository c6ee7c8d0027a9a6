#pragma once
// Contact law parameters (PFC semantics) and the per-group-pair table (like PFC's
// contact model assignment table). Parameters only; the physics is in linear.hpp.
#include "engine/core/types.hpp"

#include <map>
#include <utility>

namespace triax {

// Linear model with Coulomb slider, optional viscous dashpot, optional contact bond
// strengths (used when bond_contacts() installs bonds), optional rolling resistance.
struct ContactLaw {
    double kn = 1e6;          // N/m, normal contact stiffness (PFC linear kn)
    double ks = 1e6;          // N/m, shear contact stiffness
    double friction = 0.5;    // Coulomb coefficient mu (slider)
    // Critical damping ratio of the normal dashpot (PFC dp_nratio), 0 = off.
    // The dashpot force is -2 beta sqrt(m_eff kn) v_n and may be tensile.
    double normal_damping_ratio = 0.0;
    // Rolling resistance (rrlinear-like): kr = rolling_stiffness_factor * ks * Rbar^2,
    // |M_r| <= rolling_friction * Rbar * Fn. rolling_friction = 0 switches it off.
    double rolling_friction = 0.0;
    double rolling_stiffness_factor = 1.0;
    // Whether this pair may carry tension while bonded (contact bond) — bonds are only
    // created by World::bond_contacts; these are the default strengths it uses.
    double bond_normal_strength = 0.0;  // N
    double bond_shear_strength = 0.0;   // N
    // Friction of an intact bond's shear strength (Mohr-Coulomb bond, like the cohesion +
    // sigma tan(phi) shear strength of PFC's parallel bond and flat joint): a bonded
    // contact in compression breaks in shear at ss (1 - damage) + bond_friction Fn.
    // 0 = PFC contact bond (breaks at ss whatever the normal force).
    double bond_friction = 0.0;
    // Cement neck of an intact bond (linear.hpp): it also holds a rolling moment below
    // (rolling_friction + bond_rolling_friction (1 - damage)) Rbar Fn and cracks there (the
    // bond keeps its cohesion). 0 = the bond transmits no moment (PFC's contact bond).
    double bond_rolling_friction = 0.0;

    bool needs_rolling() const { return rolling_friction > 0.0 || bond_rolling_friction > 0.0; }
    void validate(const char* where) const;
};

// Symmetric table (group a, group b) -> law, with a default for unlisted pairs.
class ContactLawTable {
public:
    void set_default(const ContactLaw& law) { law.validate("default contact law"); default_ = law; }
    void set(int group_a, int group_b, const ContactLaw& law) {
        law.validate("contact law");
        table_[key(group_a, group_b)] = law;
    }
    const ContactLaw& get(int group_a, int group_b) const {
        auto it = table_.find(key(group_a, group_b));
        return it == table_.end() ? default_ : it->second;
    }
    const ContactLaw& default_law() const { return default_; }
    const std::map<std::pair<int, int>, ContactLaw>& entries() const { return table_; }

private:
    static std::pair<int, int> key(int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); }
    ContactLaw default_{};
    std::map<std::pair<int, int>, ContactLaw> table_;
};

inline void ContactLaw::validate(const char* where) const {
    auto bad = [&](const char* field, const char* why) {
        throw InputError(std::string(where) + ": field '" + field + "' " + why);
    };
    if (!(kn > 0)) bad("kn", "must be > 0 N/m");
    if (!(ks >= 0)) bad("ks", "must be >= 0 N/m");
    if (!(friction >= 0)) bad("friction", "must be >= 0");
    if (!(normal_damping_ratio >= 0 && normal_damping_ratio < 1)) bad("normal_damping_ratio", "must be in [0, 1)");
    if (!(rolling_friction >= 0)) bad("rolling_friction", "must be >= 0");
    if (!(rolling_stiffness_factor >= 0)) bad("rolling_stiffness_factor", "must be >= 0");
    if (!(bond_normal_strength >= 0)) bad("bond_normal_strength", "must be >= 0 N");
    if (!(bond_shear_strength >= 0)) bad("bond_shear_strength", "must be >= 0 N");
    if (!(bond_friction >= 0)) bad("bond_friction", "must be >= 0");
    if (!(bond_rolling_friction >= 0)) bad("bond_rolling_friction", "must be >= 0");
}

}  // namespace triax
