// The step's roles on their own: the contact loop over an evaluator other than the linear
// law (the loop owns geometry, slots and the zero-force invariant; the evaluator only the
// physics), the gather's Newton's third law, and the executor's contract (every block of
// every phase once per step, steps until the recipe asks for a rebuild, the same on both
// paths).
#include "engine/contact/linear.hpp"
#include "engine/core/step/contact_forces.hpp"
#include "engine/core/step/force_gather.hpp"
#include "engine/core/step/step_executor.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <vector>

using namespace triax;

namespace {

// A normal-only spring, F = k overlap n on the second body (N), stored energy 0.5 k overlap^2.
struct NormalSpring {
    struct Params { double k; };
    using Kinematics = LinearContact::Kinematics;
    using History = LinearContact::History;
    using Outcome = LinearContact::Outcome;
    template <bool kRolling, bool kStateEnergy = true>
    static Outcome evaluate(const Params& p, const Kinematics& k, History& h) {
        Outcome o;
        o.moment.setZero();
        o.force.setZero();
        if (k.overlap <= 0.0) return o;
        o.active = true;
        h.normal_force = p.k * k.overlap;
        o.force = h.normal_force * k.n;
        if (kStateEnergy) o.strain = 0.5 * p.k * k.overlap * k.overlap;
        return o;
    }
};

}  // namespace

TEST_CASE("contact forces over any evaluator: slots, opened contacts, gather", "[engine][contact]") {
    ParticleArrays pa;
    const double r = 1e-3, overlap = 1e-5, k = 2e4;
    pa.add(Vec3(0, 0, 0), r, 2650.0, 0);
    pa.add(Vec3(2 * r - overlap, 0, 0), r, 2650.0, 0);  // touches particle 0 along +x
    pa.add(Vec3(0, 3 * r, 0), r, 2650.0, 0);            // apart from particle 0
    ContactStore c;
    c.resize(2);
    for (long s = 0; s < 2; ++s) c.reset_history(s);
    c.i = {0, 0};
    c.j = {1, 2};
    c.law = {0, 0};
    c.active[1] = 1;  // was touching: must open and hold zero force
    c.force_on_j[1] = Vec3(1, 2, 3);
    const std::vector<NormalSpring::Params> params{{k}};

    for (const bool state_energy : {false, true}) {
        const ContactSums sums = step::ContactForces<NormalSpring>::block(c, pa, params, 1e-6, 0, false, state_energy);
        CHECK(c.active[0] == 1);
        CHECK(c.force_on_j[0].x() == Approx(k * overlap).epsilon(1e-9));
        CHECK(c.force_on_j[0].y() == 0.0);
        CHECK(c.force_on_j[0].z() == 0.0);
        CHECK(c.torque_on_i[0].norm() == 0.0);  // central force
        CHECK(c.torque_on_j[0].norm() == 0.0);
        CHECK(c.active[1] == 0);
        CHECK(c.force_on_j[1] == Vec3::Zero());
        if (state_energy) CHECK(sums.strain == Approx(0.5 * k * overlap * overlap).epsilon(1e-9));
        else CHECK(sums.strain == 0.0);
    }

    // Gather: particle 0 is side i of both slots, 1 and 2 are side j.
    const std::vector<int> adj_start{0, 2, 3, 4}, adj{0 * 2 + 0, 1 * 2 + 0, 0 * 2 + 1, 1 * 2 + 1};
    const std::vector<int> wall_adj_start{0, 0, 0, 0}, wall_adj;
    const WallContactStore wc;
    const std::vector<ContactLaw> laws{ContactLaw{}};
    const step::ForceGather gather{c, wc, adj_start, adj, wall_adj_start, wall_adj, laws, true};
    const step::GatheredForce f0 = gather(0, r), f1 = gather(1, r), f2 = gather(2, r);
    CHECK(f0.force == -f1.force);  // Newton's third law, bitwise
    CHECK(f2.force == Vec3::Zero());
    CHECK(f0.stiffness == laws[0].kn + laws[0].ks);  // one active contact
    CHECK(f2.stiffness == 0.0);
}

namespace {

// A recipe that counts what the executor runs; asks for a rebuild after `rebuild_after` steps.
struct CountingRecipe {
    long contact_blocks = 5, body_blocks = 3, rebuild_after = 1000000;
    std::vector<std::atomic<int>> contact_runs = std::vector<std::atomic<int>>(5);
    std::vector<std::atomic<int>> body_runs = std::vector<std::atomic<int>>(3);
    std::atomic<int> wall_runs{0};
    long steps = 0, lasts = 0;
    std::atomic<bool> order_ok{true};
    void begin(bool last) { lasts += last; }
    long contact_block_count() const { return contact_blocks; }
    void contact_block(long b) { ++contact_runs[b]; }
    void wall_contacts() { ++wall_runs; }
    long body_block_count() const { return body_blocks; }
    void body_block(long b) {
        // Every contact block of this step is done before any body block.
        for (auto& c : contact_runs)
            if (c.load() != steps + 1) order_ok = false;
        ++body_runs[b];
    }
    bool end() { return ++steps % rebuild_after != 0; }
};

}  // namespace

TEST_CASE("the step executor runs every block of every phase once per step", "[engine][parallel]") {
    for (const int threads : {1, 2, 3}) {
        for (const long particles : {100L, 5000L}) {  // below and above the team threshold
            CountingRecipe recipe;
            recipe.rebuild_after = 4;
            const step::StepExecutor executor(threads, particles);
            long done = 0, runs = 0;
            while (done < 10) {
                done = executor.run(recipe, done, 10);
                ++runs;
            }
            CHECK(done == 10);
            CHECK(recipe.steps == 10);
            CHECK(recipe.lasts == 1);  // only the call's last step is flagged last
            CHECK(recipe.wall_runs == 10);
            CHECK(recipe.order_ok);
            for (auto& c : recipe.contact_runs) CHECK(c == 10);
            for (auto& b : recipe.body_runs) CHECK(b == 10);
            // One step per run without a team; with a team, runs end at rebuilds (4, 8) and the end.
            CHECK(runs == (threads > 1 && particles >= step::kParallelMin ? 3 : 10));
        }
    }
}
