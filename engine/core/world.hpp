#pragma once
// triax::World: one DEM model (spheres, walls, clumps, contacts, energies) and its
// time step. No global state: several Worlds may run side by side, each with its own
// OpenMP thread count. SI units throughout. See docs/engine.md for usage.
//
// One step (cycle; the recipe in world_step.cpp, its roles under engine/core/step/,
// engine/integrate/, engine/boundary/ and engine/energy/):
//   rebuild the neighbour list if something moved more than skin/2
//   contact forces into per-contact slots (parallel over contacts; walls on one thread)
//   gather per particle in a fixed order + external + gravity, and integrate the spheres
//     (central difference + local damping; parallel over particles)
//   book energies, check for instability, integrate clumps rigidly, move walls
#include "engine/contact/contact_law.hpp"
#include "engine/contact/contact_store.hpp"
#include "engine/core/clump.hpp"
#include "engine/core/particle_arrays.hpp"
#include "engine/core/types.hpp"
#include "engine/core/walls.hpp"
#include "engine/energy/energy_ledger.hpp"
#include "engine/neighbor/cell_list.hpp"

#include <limits>
#include <optional>
#include <vector>

namespace triax {

class World {
public:
    World() = default;

    // ---- building the model ---------------------------------------------------
    // Adds a solid sphere (radius m, density kg/m^3) with a group tag; returns its index.
    int add_sphere(const Vec3& position, double radius, double density, int group = 0);
    int add_plane_wall(const Vec3& point, const Vec3& normal, int group = 0);
    int add_cylinder_wall(const Vec3& base, const Vec3& axis, double radius, double height, int group = 0);
    // Turns existing free spheres into one rigid clump; returns the clump index.
    int add_clump(const std::vector<int>& members);

    ParticleArrays& particles() { return particles_; }
    const ParticleArrays& particles() const { return particles_; }
    std::size_t particle_count() const { return particles_.size(); }
    PlaneWall& plane_wall(int k) { return plane_walls_.at(k); }
    CylinderWall& cylinder_wall(int k) { return cylinder_walls_.at(k); }
    const PlaneWall& plane_wall(int k) const { return plane_walls_.at(k); }
    const CylinderWall& cylinder_wall(int k) const { return cylinder_walls_.at(k); }
    Clump& clump(int k) { return clumps_.at(k); }
    const Clump& clump(int k) const { return clumps_.at(k); }
    std::size_t plane_wall_count() const { return plane_walls_.size(); }
    std::size_t cylinder_wall_count() const { return cylinder_walls_.size(); }
    std::size_t clump_count() const { return clumps_.size(); }
    // Sets a clump's velocity (and spin) and moves its members' velocities with it.
    void set_clump_velocity(int k, const Vec3& velocity, const Vec3& angular_velocity = Vec3::Zero());

    // ---- contact laws ----------------------------------------------------------
    void set_default_contact_law(const ContactLaw& law);
    void set_contact_law(int group_a, int group_b, const ContactLaw& law);
    const ContactLawTable& contact_laws() const { return laws_; }

    // Installs contact bonds (PFC "contact bond install") on every pair of spheres of
    // groups (a, b) whose gap is <= gap_tolerance (m), touching pairs included. Bonded
    // pairs start unloaded (the gap at install is kept as a reference gap). Strengths
    // in N. Returns the number of bonds installed.
    int bond_contacts(int group_a, int group_b, double gap_tolerance, double normal_strength,
                      double shear_strength);
    long broken_bonds_tension() const { return broken_tension_; }
    long broken_bonds_shear() const { return broken_shear_; }
    long intact_bond_count() const;

    // Ball-ball contact history (see contact_store.hpp). Slots with active == 0 are
    // neighbour candidates, not contacts. Writable between cycles.
    ContactStore& contacts() { return contacts_; }
    const ContactStore& contacts() const { return contacts_; }
    WallContactStore& wall_contacts() { return wall_contacts_; }
    const WallContactStore& wall_contacts() const { return wall_contacts_; }
    // The law of ball-ball slot k / wall slot k.
    const ContactLaw& contact_law_of(std::size_t k) const { return resolved_laws_.at(contacts_.law[k]); }
    const ContactLaw& wall_contact_law_of(std::size_t k) const { return resolved_laws_.at(wall_contacts_.law[k]); }
    long active_contact_count() const;       // ball-ball
    long active_wall_contact_count() const;

    // ---- time stepping ----------------------------------------------------------
    // PFC-like estimate: min over bodies of sqrt(m / k_trans) and sqrt(I / k_rot), with k
    // summed over the body's current contacts (kn + ks; rotational ks r^2), or the
    // stiffest law its group can meet when it has none; times `safety`.
    double critical_time_step(double safety = 0.8) const;
    void set_time_step(double dt);
    double time_step() const { return dt_; }
    void set_local_damping(double alpha);            // PFC local damping coefficient, default 0.7
    double local_damping() const { return alpha_; }
    // Density scaling for quasi-static stages: each body's inertial mass (and inertia)
    // is raised each step to m_in = max(m, 4 k dt^2) (k = its contact stiffness sum,
    // rotational k r^2), so the chosen dt is stable whatever the true masses. Gravity
    // still uses the true mass; kinetic energy uses the inertial mass. Dynamics are
    // then not physical in time — only the equilibrium states are.
    void set_density_scaling(bool on) { density_scaling_ = on; }
    bool density_scaling() const { return density_scaling_; }
    // Inertial mass of each body at the last step (= its mass without density scaling):
    // what the quasi-static checks (inertial number) must use.
    const std::vector<double>& inertial_masses() const { return inertial_mass_; }
    void set_gravity(const Vec3& g) { gravity_ = g; }
    const Vec3& gravity() const { return gravity_; }
    void set_threads(int n);
    int threads() const { return threads_; }
    // Verlet skin (m). Default: 0.1 x the smallest radius added so far (when unset).
    void set_skin(double skin);
    double skin() const;
    // A particle leaving this box throws SimulationError. Unset = no box.
    void set_domain(const Vec3& lo, const Vec3& hi);
    // Kinetic energy above this (J) throws SimulationError. Default: no limit.
    void set_max_kinetic_energy(double joules) { max_kinetic_ = joules; }
    void set_energy_tracking(bool on) { track_energy_ = on; }

    // Advances n mechanical steps. Throws SimulationError on instability.
    void cycle(long n);
    long step() const { return step_; }
    double time() const { return time_; }

    // ---- measures ----------------------------------------------------------------
    EnergyLedger& energy() { return energy_; }
    const EnergyLedger& energy() const { return energy_; }
    double kinetic_energy() const;
    // Mean |net force| over free bodies (spheres not in clumps, free clumps) (N).
    double mean_unbalanced_force() const;
    // Mean |contact force| over active contacts, walls included (N).
    double mean_contact_force() const;
    // PFC's mechanical ratio: mean unbalanced force / mean contact force (0 if no contacts).
    double unbalanced_force_ratio() const;
    long neighbor_rebuild_count() const { return rebuilds_; }

    // Forces a neighbour-list rebuild at the next step (after editing positions by hand).
    void invalidate_neighbors() { need_rebuild_ = true; }

private:
    void ensure_ready();
    void rebuild_neighbors();
    int law_index(int group_a, int group_b);
    void refresh_resolved_laws();
    // One step as a recipe over the roles (world_step.cpp), run by step::StepExecutor.
    class Step;
    void update_clump_members(Clump& c);
    double contact_stiffness_fallback(int group) const;

    ParticleArrays particles_;
    std::vector<PlaneWall> plane_walls_;
    std::vector<CylinderWall> cylinder_walls_;
    std::vector<Clump> clumps_;
    ContactLawTable laws_;
    std::vector<ContactLaw> resolved_laws_;
    std::vector<std::pair<int, int>> resolved_keys_;
    ContactStore contacts_;
    WallContactStore wall_contacts_;
    CellList cells_;
    EnergyLedger energy_;

    // Per-particle gather lists (CSR): entries are slot*2 + side (0: particle is i, 1: j).
    std::vector<int> adj_start_, adj_;
    std::vector<int> wall_adj_start_, wall_adj_;
    std::vector<Vec3> rebuild_position_;
    std::vector<double> wall_travel_;     // per wall since rebuild (planes then cylinders)
    std::vector<double> inertial_mass_, inertial_inertia_;
    std::vector<double> stiffness_sum_, rot_stiffness_sum_;

    double dt_ = 0.0;
    double alpha_ = 0.7;
    bool density_scaling_ = false;
    Vec3 gravity_ = Vec3::Zero();
    int threads_ = 1;
    std::optional<double> skin_;
    double min_radius_ = std::numeric_limits<double>::infinity();
    std::optional<std::pair<Vec3, Vec3>> domain_;
    double max_kinetic_ = std::numeric_limits<double>::infinity();
    bool track_energy_ = true;
    bool need_rebuild_ = true;
    long step_ = 0;
    double time_ = 0.0;
    long broken_tension_ = 0, broken_shear_ = 0;
    long rebuilds_ = 0;
    bool any_rolling_ = false;
};

}  // namespace triax
