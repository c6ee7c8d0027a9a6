#pragma once
// Pair-keyed contact history as a structure of arrays. One slot per candidate pair of
// the neighbour list (i < j, sorted by (i, j)); a slot is `active` when the spheres
// overlap (after reference gap and creep offset) or are bonded. History survives
// neighbour-list rebuilds (slots are merged by key) and is reset when a contact opens.
//
// Sign conventions (engine-internal, SI): normal n points from i to j;
// normal_force > 0 is compression; shear_force is the shear force ON j (the force on i
// is its opposite); rolling_moment is the rolling resistance moment ON j.
//
// Crushing (grain_crushing.hpp) writes plastic_overlap between cycles (m, the linear law
// uses overlap - plastic_overlap; kept while the grains still overlap geometrically).
// The creep mechanism (engine/creep) reads and writes between cycles: damage (bond
// corrosion in [0, 1], bond strengths are scaled by 1 - damage), contact_age (s, the
// rate-and-state friction's state theta), creep_reference_shear (N, |Fs| at the stage's
// start: the loading step's displacement renews the state at the stage's first creep
// update; negative once counted), shear_force (the creep slip unloads
// the shear spring). All reset when a contact opens: a new contact is young.
#include "engine/core/types.hpp"

#include <cstdint>
#include <vector>

namespace triax {

struct ContactStore {
    // Key and law.
    std::vector<int> i, j;
    std::vector<int> law;                    // index into World's resolved law list
    // History / state.
    std::vector<std::uint8_t> active;        // 1 when touching or bonded this step
    std::vector<double> normal_force;        // N, compression positive (elastic + dashpot)
    std::vector<Vec3> shear_force;           // N, on j
    std::vector<Vec3> rolling_moment;        // N m, on j
    std::vector<std::uint8_t> bonded;        // contact bond intact
    std::vector<std::uint8_t> neck_cracked;  // the intact bond's cement neck cracked: it holds no moment
    std::vector<double> bond_normal_strength;  // N (tensile strength)
    std::vector<double> bond_shear_strength;   // N
    std::vector<double> reference_gap;       // m, gap at bond installation (bonded pairs start unloaded)
    std::vector<double> plastic_overlap;     // m, crushed (lost) overlap of a crushable grain contact
    std::vector<double> damage;              // [0, 1], bond corrosion
    std::vector<double> contact_age;         // s, rate-and-state state theta (0: none yet)
    std::vector<double> creep_reference_shear;  // N, |Fs| at the stage's start (< 0: counted)
    // Per-step results (slots gathered per particle in a fixed order). A slot that is not
    // active holds zero force and torques: the World's gather adds every candidate slot,
    // so a caller that clears `active` between cycles must clear these three as well.
    std::vector<Vec3> force_on_j;            // N, total contact force on j (on i: minus this)
    std::vector<Vec3> torque_on_i, torque_on_j;  // N m
    std::vector<Vec3> contact_point;         // m
    std::vector<double> overlap;             // m, effective overlap used by the law (negative = gap)

    std::size_t size() const { return i.size(); }

    void clear() { resize(0); }

    void resize(std::size_t n) {
        i.resize(n); j.resize(n); law.resize(n); active.resize(n);
        normal_force.resize(n); shear_force.resize(n); rolling_moment.resize(n);
        bonded.resize(n); neck_cracked.resize(n); bond_normal_strength.resize(n); bond_shear_strength.resize(n);
        reference_gap.resize(n); plastic_overlap.resize(n); damage.resize(n);
        contact_age.resize(n); creep_reference_shear.resize(n);
        force_on_j.resize(n); torque_on_i.resize(n); torque_on_j.resize(n);
        contact_point.resize(n); overlap.resize(n);
    }

    // Fresh slot with no history.
    void reset_history(std::size_t k) {
        normal_force[k] = 0.0;
        shear_force[k].setZero();
        rolling_moment[k].setZero();
        bonded[k] = 0;
        neck_cracked[k] = 0;
        bond_normal_strength[k] = 0.0;
        bond_shear_strength[k] = 0.0;
        reference_gap[k] = 0.0;
        plastic_overlap[k] = 0.0;
        damage[k] = 0.0;
        contact_age[k] = 0.0;
        creep_reference_shear[k] = 0.0;
        active[k] = 0;
    }

    // Copies the history of slot `from` of `other` into slot `to`.
    void copy_history(std::size_t to, const ContactStore& other, std::size_t from) {
        active[to] = other.active[from];
        normal_force[to] = other.normal_force[from];
        shear_force[to] = other.shear_force[from];
        rolling_moment[to] = other.rolling_moment[from];
        bonded[to] = other.bonded[from];
        neck_cracked[to] = other.neck_cracked[from];
        bond_normal_strength[to] = other.bond_normal_strength[from];
        bond_shear_strength[to] = other.bond_shear_strength[from];
        reference_gap[to] = other.reference_gap[from];
        plastic_overlap[to] = other.plastic_overlap[from];
        damage[to] = other.damage[from];
        contact_age[to] = other.contact_age[from];
        creep_reference_shear[to] = other.creep_reference_shear[from];
    }
};

// Particle-wall contacts: same history fields, keyed by (particle, wall). wall_kind 0
// = plane wall, 1 = cylinder wall; wall = index in that kind's list. The normal points
// from the wall to the particle; shear_force is the force on the particle.
struct WallContactStore {
    std::vector<int> particle, wall;
    std::vector<std::uint8_t> wall_kind;
    std::vector<int> law;
    std::vector<std::uint8_t> active;
    std::vector<double> normal_force;
    std::vector<Vec3> shear_force;
    std::vector<Vec3> force_on_particle;
    std::vector<Vec3> torque_on_particle;
    std::vector<Vec3> contact_point;
    std::vector<double> overlap;

    std::size_t size() const { return particle.size(); }
    void resize(std::size_t n) {
        particle.resize(n); wall.resize(n); wall_kind.resize(n); law.resize(n); active.resize(n);
        normal_force.resize(n); shear_force.resize(n); force_on_particle.resize(n);
        torque_on_particle.resize(n); contact_point.resize(n); overlap.resize(n);
    }
    void reset_history(std::size_t k) {
        active[k] = 0; normal_force[k] = 0.0; shear_force[k].setZero();
    }
    void copy_history(std::size_t to, const WallContactStore& o, std::size_t from) {
        active[to] = o.active[from]; normal_force[to] = o.normal_force[from];
        shear_force[to] = o.shear_force[from];
    }
};

}  // namespace triax
