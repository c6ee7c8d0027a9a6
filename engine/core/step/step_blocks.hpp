#pragma once
// The fixed blocks a step is cut into, and how they are handed to threads.
//
// Every parallel phase works on fixed-size blocks whose partial sums are reduced serially
// in block order, so results do not depend on the thread count or on which thread ran a
// block. Blocks are handed out dynamically: the work per item is uneven (a specimen's
// grains come first and have more contacts than its membrane spheres; far candidate slots
// cost almost nothing), and static halves leave one of two threads idle for up to half
// of the step.
#include <atomic>
#include <cstdint>

namespace triax::step {

constexpr long kContactBlock = 1024;  // ball-ball contact slots per block
constexpr long kParticleBlock = 256;  // particles per block (gather + integration)
// Below this many items a parallel region costs more than it saves (thread wake-up);
// the block structure is the same either way, so results do not change.
constexpr long kParallelMin = 4096;

constexpr long block_count(long items, long block) { return (items + block - 1) / block; }

// Blocks [0, n) handed out from both ends: thread 0 takes them from the front, the other
// threads from the back. Contact slots are sorted by their first particle and particle
// blocks follow the particle index, so a thread tends to gather the forces that it wrote
// itself and to integrate the particles whose contacts it computed (fewer cache lines
// moving between the cores than with one counter, where the blocks' owners are random),
// and the split point still follows the load. Which thread runs a block does not change
// the results (partial sums per block, reduced in block order).
class TwoEndedBlocks {
public:
    void reset(long n) { ends_.store(static_cast<std::uint64_t>(n), std::memory_order_relaxed); }
    // The next block for thread `tid`, or -1 when none is left.
    long take(int tid) {
        std::uint64_t e = ends_.load(std::memory_order_relaxed);
        while (true) {
            const std::uint64_t front = e >> 32, back = e & 0xffffffffu;
            if (front >= back) return -1;
            const std::uint64_t next = tid == 0 ? ((front + 1) << 32) | back : (front << 32) | (back - 1);
            if (ends_.compare_exchange_weak(e, next, std::memory_order_relaxed))
                return static_cast<long>(tid == 0 ? front : back - 1);
        }
    }

private:
    std::atomic<std::uint64_t> ends_{0};  // front in the high 32 bits, back (exclusive) in the low
};

}  // namespace triax::step
