#pragma once
// Broad phase: a cell list with a Verlet skin. build() returns every pair (i < j) whose
// surfaces are closer than `skin`, sorted by (i, j); the World keeps that list until
// some particle (or wall) has moved more than skin/2 since the build, so no contact can
// be missed in between. Cost is linear in N: counting sort into cells of edge
// 2 r_max + skin, then per particle a search of its own and the 26 neighbouring cells for
// later ids within reach (each cell's members stored contiguously).
#include "engine/core/types.hpp"

#include <cstdint>
#include <vector>

namespace triax {

class CellList {
public:
    // Candidate pairs (i < j, sorted). Pairs of the same clump (clump_id >= 0) are skipped.
    // `threads` is the OpenMP thread count; the result does not depend on it.
    void build(const std::vector<Vec3>& position, const std::vector<double>& radius,
               const std::vector<int>& clump_id, double skin, int threads,
               std::vector<int>& pair_i, std::vector<int>& pair_j);

private:
    struct CellMember {
        Vec3 centre;  // m
        double radius;  // m
        int id, clump;
    };
    std::vector<int> cell_start_;          // CSR offsets, size n_cells + 1
    std::vector<CellMember> members_;      // particles grouped by cell, ascending ids in each
    std::vector<std::int64_t> cell_of_;
    std::vector<std::vector<int>> thread_i_, thread_j_, thread_found_;  // per thread, kept between builds
};

}  // namespace triax
