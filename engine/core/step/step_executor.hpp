#pragma once
// The executor: runs the steps of a recipe on the World's threads. It owns all of the
// OpenMP and none of the physics.
//
// A recipe (World::Step) provides, for one step:
//   begin(bool last)         serial: per-step set-up; `last` = the cycle() call's last step
//   contact_block_count(), contact_block(b)   contact forces, one block of slots
//   wall_contacts()          wall contact forces: one thread, beside the contact blocks
//   body_block_count(), body_block(b)         gather + integration, one block of particles
//   end() -> bool            serial: reductions, clumps, walls, checks, clock; false when
//                            the neighbour list must be rebuilt before the next step
// The phases meet in this order on every path, and blocks are reduced in block order by
// the recipe, so a step's results do not depend on the path or the thread count.
#include "engine/core/step/step_blocks.hpp"

#include <omp.h>

#include <atomic>
#include <exception>

namespace triax::step {

class StepExecutor {
public:
    // `threads`: the World's thread count; `particles`: the model's size, which decides
    // whether a thread team pays for itself.
    StepExecutor(int threads, long particles) : threads_(threads), team_(threads > 1 && particles >= kParallelMin) {}

    // Runs steps [done, n) until the call's end or until the recipe asks for a neighbour
    // rebuild; returns the number of steps done so far. Without a team it runs one step.
    template <class Recipe>
    long run(Recipe& recipe, long done, long n) const {
        return team_ ? run_team(recipe, done, n) : run_one(recipe, done, n);
    }

private:
    // One thread, or a model too small to share: the phases in order, each parallel only
    // when it has enough items.
    template <class Recipe>
    long run_one(Recipe& recipe, long done, long n) const {
        recipe.begin(done + 1 == n);
        const long nc = recipe.contact_block_count(), np = recipe.body_block_count();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (threads_ > 1 && nc * kContactBlock >= kParallelMin)
        for (long b = 0; b < nc; ++b) recipe.contact_block(b);
        recipe.wall_contacts();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (threads_ > 1 && np * kParticleBlock >= kParallelMin)
        for (long b = 0; b < np; ++b) recipe.body_block(b);
        recipe.end();
        return done + 1;
    }

    // Thread team: one OpenMP region for a run of steps (until the neighbour list must be
    // rebuilt or the call ends), three barriers per step. A region per phase costs a fork
    // and a join each, i.e. four thread wake-ups per step (libgomp: a futex each under
    // OMP_WAIT_POLICY=passive). An exception in the serial phase ends the run and is
    // rethrown here.
    template <class Recipe>
    long run_team(Recipe& recipe, long done, long n) const {
        TwoEndedBlocks contact_blocks, body_blocks;
        std::atomic<bool> leave{false};
        std::exception_ptr error;
        recipe.begin(done + 1 == n);
        contact_blocks.reset(recipe.contact_block_count());
        body_blocks.reset(recipe.body_block_count());
#pragma omp parallel num_threads(threads_)
        {
            const int tid = omp_get_thread_num(), nt = omp_get_num_threads();
            while (true) {
                // Contacts: the last thread takes the wall contacts first, then joins the blocks.
                if (tid == nt - 1) recipe.wall_contacts();
                for (long b; (b = contact_blocks.take(tid)) >= 0;) recipe.contact_block(b);
#pragma omp barrier
                for (long b; (b = body_blocks.take(tid)) >= 0;) recipe.body_block(b);
#pragma omp barrier
                if (tid == 0) {
                    // Serial rest of the step, then the next step's set-up (the others wait).
                    try {
                        const bool keep_list = recipe.end();
                        ++done;
                        if (done >= n || !keep_list) leave.store(true, std::memory_order_relaxed);
                        else recipe.begin(done + 1 == n);
                    } catch (...) {
                        error = std::current_exception();
                        leave.store(true, std::memory_order_relaxed);
                    }
                    contact_blocks.reset(recipe.contact_block_count());
                    body_blocks.reset(recipe.body_block_count());
                }
#pragma omp barrier
                if (leave.load(std::memory_order_relaxed)) break;
            }
        }
        if (error) std::rethrow_exception(error);
        return done;
    }

    int threads_;
    bool team_;
};

}  // namespace triax::step
