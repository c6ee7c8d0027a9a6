// World::cycle: the time step as a short recipe over roles, run by an executor.
//
//   per run of steps   rebuild the neighbour list when something moved more than skin/2
//   per step           contact forces      ball-ball slots, blocks in parallel
//                                           (step/contact_forces.hpp) and wall slots on one
//                                           thread beside them (step/wall_contact_forces.hpp),
//                                           both over the LinearContact evaluator
//                      gather + integrate  per particle (step/force_gather.hpp,
//                                           integrate/central_difference.hpp), blocks in parallel
//                      serial end          energy ledger (energy/step_sums.hpp), clumps
//                                           (integrate/rigid_clump.hpp), walls
//                                           (boundary/wall_motion.hpp), kinetic-energy limit,
//                                           clock
// Threading is the executor's (step/step_executor.hpp): which thread runs a block never
// changes the results, since every reduction goes through per-block sums in block order.
#include "engine/boundary/wall_motion.hpp"
#include "engine/contact/linear.hpp"
#include "engine/core/step/contact_forces.hpp"
#include "engine/core/step/force_gather.hpp"
#include "engine/core/step/step_blocks.hpp"
#include "engine/core/step/step_executor.hpp"
#include "engine/core/step/wall_contact_forces.hpp"
#include "engine/core/world.hpp"
#include "engine/energy/step_sums.hpp"
#include "engine/integrate/central_difference.hpp"
#include "engine/integrate/rigid_clump.hpp"
#include "engine/integrate/sphere_lanes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace triax {

// One step of the World, as the executor runs it (step_executor.hpp names the phases).
// Holds the scratch of one cycle() call: the evaluator's parameters and the per-block sums.
class World::Step {
public:
    using Evaluator = LinearContact;

    explicit Step(World& w) : w_(w) {}

    // Laws do not change during a run of steps; a rebuild may add a resolved law.
    void load_laws() {
        params_.clear();
        for (const ContactLaw& l : w_.resolved_laws_) params_.push_back(Evaluator::Params::from(l));
    }

    // State energies (strain, bond strain, kinetic) are functions of the state: a caller can
    // only read the ledger between cycle() calls, so they are computed on the call's last
    // step (the same code, so the same numbers) and skipped on the others (two divisions
    // per contact). Kinetic energy is also needed on every step under a kinetic-energy limit.
    void begin(bool last) {
        state_energy_ = last;
        kinetic_ = last || w_.max_kinetic_ < std::numeric_limits<double>::infinity();
        contact_blocks_.assign(step::block_count(static_cast<long>(w_.contacts_.size()), step::kContactBlock), {});
        body_blocks_.assign(step::block_count(static_cast<long>(w_.particles_.size()), step::kParticleBlock), {});
        wall_sums_ = ContactSums{};
    }

    long contact_block_count() const { return static_cast<long>(contact_blocks_.size()); }
    void contact_block(long b) {
        contact_blocks_[b] = step::ContactForces<Evaluator>::block(w_.contacts_, w_.particles_, params_, w_.dt_, b,
                                                                   w_.any_rolling_, state_energy_);
    }

    void wall_contacts() {
        wall_sums_ = step::WallContactForces<Evaluator>::all(w_.wall_contacts_, w_.plane_walls_, w_.cylinder_walls_,
                                                             w_.particles_, params_, w_.dt_, w_.any_rolling_);
    }

    long body_block_count() const { return static_cast<long>(body_blocks_.size()); }
    void body_block(long b);

    // Returns false when the neighbour list must be rebuilt before the next step.
    bool end();

private:
    void integrate_clumps();

    World& w_;
    std::vector<Evaluator::Params> params_;
    bool state_energy_ = true, kinetic_ = true;
    std::vector<ContactSums> contact_blocks_;
    std::vector<BodySums> body_blocks_;
    ContactSums wall_sums_;
};

void World::cycle(long n) {
    if (n < 0) throw InputError("cycle: field 'steps' must be >= 0, got " + std::to_string(n));
    if (n == 0) return;
    if (!(dt_ > 0)) throw InputError("cycle: time step not set; call set_time_step(critical_time_step()) first");
    if (particles_.size() == 0) throw InputError("cycle: the world has no particles");
    Step recipe(*this);
    const step::StepExecutor executor(threads_, static_cast<long>(particles_.size()));
    for (long done = 0; done < n;) {
        ensure_ready();
        if (need_rebuild_) rebuild_neighbors();  // serial merge; the cell search is parallel
        recipe.load_laws();                      // a rebuild may meet a new group pair
        done = executor.run(recipe, done, n);    // until the call ends or a rebuild is due
    }
}

// Gather then integrate, particle by particle: the forces a thread gathers are still in its
// cache when it integrates them. Also the drift since the last rebuild (Verlet skin).
void World::Step::body_block(long b) {
    World& w = w_;
    ParticleArrays& pa = w.particles_;
    const step::ForceGather gather{w.contacts_, w.wall_contacts_, w.adj_start_, w.adj_, w.wall_adj_start_,
                                   w.wall_adj_, w.resolved_laws_, w.density_scaling_};
    const bool has_domain = w.domain_.has_value();
    const SphereIntegrator integrate{w.dt_, w.alpha_, w.gravity_, w.density_scaling_, kinetic_, has_domain,
                                     has_domain ? w.domain_->first : Vec3::Zero(),
                                     has_domain ? w.domain_->second : Vec3::Zero()};
    BodySums s;
    auto track_drift = [&](long q) {
        s.max_disp2 = std::max(s.max_disp2, (pa.position[q] - w.rebuild_position_[q]).squaredNorm());
    };
    const long end = std::min(static_cast<long>(pa.size()), (b + 1) * step::kParticleBlock);
    long p = b * step::kParticleBlock;
    // Four particles at a time across SIMD lanes where the CPU has them (the same bits).
    if (simd::avx2_available()) {
        constexpr int kLanes = simd::kLaneCount;
        for (; p + kLanes <= end; p += kLanes) {
            Vec3 f[kLanes], t[kLanes];
            double kt[kLanes], kr[kLanes];
            for (int l = 0; l < kLanes; ++l) {
                const step::GatheredForce g = gather(p + l, pa.radius[p + l]);
                w.stiffness_sum_[p + l] = kt[l] = g.stiffness;
                w.rot_stiffness_sum_[p + l] = kr[l] = g.rot_stiffness;
                f[l] = g.force;
                t[l] = g.torque;
            }
            if (integrate_sphere_lanes(integrate, p, f, t, kt, kr, pa, w.inertial_mass_, w.inertial_inertia_, s)) {
                for (int l = 0; l < kLanes; ++l) track_drift(p + l);
            } else {
                for (int l = 0; l < kLanes; ++l)
                    if (integrate(p + l, f[l], t[l], kt[l], kr[l], pa, w.inertial_mass_, w.inertial_inertia_, s))
                        track_drift(p + l);
            }
        }
    }
    for (; p < end; ++p) {
        const step::GatheredForce g = gather(p, pa.radius[p]);
        w.stiffness_sum_[p] = g.stiffness;
        w.rot_stiffness_sum_[p] = g.rot_stiffness;
        if (integrate(p, g.force, g.torque, g.stiffness, g.rot_stiffness, pa, w.inertial_mass_, w.inertial_inertia_, s))
            track_drift(p);
    }
    body_blocks_[b] = s;
}

bool World::Step::end() {
    World& w = w_;
    EnergyLedger* books = w.track_energy_ ? &w.energy_ : nullptr;
    const ContactSums contacts = reduce_in_block_order(contact_blocks_, wall_sums_);
    w.broken_tension_ += contacts.broke_tension;
    w.broken_shear_ += contacts.broke_shear;
    if (books) book_contacts(*books, contacts, state_energy_);
    const BodySums bodies = reduce_in_block_order(body_blocks_);
    if (books) book_bodies(*books, bodies, kinetic_);
    if (bodies.unstable >= 0)
        throw SimulationError(w.step_, describe_instability(bodies.cause, bodies.unstable, w.particles_, w.dt_));
    const double half_skin = 0.5 * w.skin();
    if (bodies.max_disp2 > half_skin * half_skin) w.need_rebuild_ = true;
    integrate_clumps();
    if (move_walls(w.plane_walls_, w.cylinder_walls_, w.wall_travel_, w.dt_, half_skin, books)) w.need_rebuild_ = true;
    if (books && w.energy_.kinetic > w.max_kinetic_) {
        std::ostringstream why;
        why << "exploding kinetic energy: " << w.energy_.kinetic << " J exceeds the limit " << w.max_kinetic_ << " J";
        throw SimulationError(w.step_, why.str());
    }
    ++w.step_;
    w.time_ += w.dt_;
    return !w.need_rebuild_;
}

// Clumps after the spheres (their members' forces are gathered by then), in clump order.
void World::Step::integrate_clumps() {
    World& w = w_;
    const ClumpIntegrator integrate{w.dt_, w.alpha_, w.gravity_, w.density_scaling_, kinetic_, w.stiffness_sum_,
                                    w.rot_stiffness_sum_};
    EnergyLedger* books = w.track_energy_ ? &w.energy_ : nullptr;
    const double half_skin = 0.5 * w.skin();
    for (Clump& c : w.clumps_) {
        integrate(c, w.particles_, books);
        w.update_clump_members(c);
        for (int p : c.members) {
            if ((w.particles_.position[p] - w.rebuild_position_[p]).squaredNorm() > half_skin * half_skin)
                w.need_rebuild_ = true;
            if (!std::isfinite(w.particles_.position[p].squaredNorm()))
                throw SimulationError(w.step_, "non-finite position (NaN) of clump member " + std::to_string(p));
        }
    }
}

}  // namespace triax
