#include "engine/neighbor/cell_list.hpp"

#include <algorithm>
#include <cmath>
#include <omp.h>

namespace triax {

void CellList::build(const std::vector<Vec3>& position, const std::vector<double>& radius,
                     const std::vector<int>& clump_id, double skin, int threads,
                     std::vector<int>& pair_i, std::vector<int>& pair_j) {
    const int n = static_cast<int>(position.size());
    pair_i.clear();
    pair_j.clear();
    if (n < 2) return;

    Vec3 lo = position[0], hi = position[0];
    double r_max = 0.0;
    for (int p = 0; p < n; ++p) {
        lo = lo.cwiseMin(position[p]);
        hi = hi.cwiseMax(position[p]);
        r_max = std::max(r_max, radius[p]);
    }
    const double cell = 2.0 * r_max + skin;
    // Cap the grid so a far-flung particle cannot blow up memory: cells just get larger.
    long dims[3];
    double edge = cell;
    for (;;) {
        long total = 1;
        for (int a = 0; a < 3; ++a) {
            dims[a] = std::max(1L, static_cast<long>(std::floor((hi[a] - lo[a]) / edge)) + 1);
            total *= dims[a];
        }
        if (total <= 8L * n + 64) break;
        edge *= 1.5;
    }
    const long nx = dims[0], ny = dims[1], nz = dims[2];
    const long n_cells = nx * ny * nz;

    cell_of_.resize(n);
    cell_start_.assign(n_cells + 1, 0);
    for (int p = 0; p < n; ++p) {
        long c[3];
        for (int a = 0; a < 3; ++a)
            c[a] = std::min(dims[a] - 1, static_cast<long>((position[p][a] - lo[a]) / edge));
        cell_of_[p] = (c[2] * ny + c[1]) * nx + c[0];
        ++cell_start_[cell_of_[p] + 1];
    }
    for (long c = 0; c < n_cells; ++c) cell_start_[c + 1] += cell_start_[c];
    // Each cell's members (ascending ids) as one contiguous run of centre, radius, id, clump.
    members_.resize(n);
    {
        std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
        for (int p = 0; p < n; ++p) members_[fill[cell_of_[p]]++] = {position[p], radius[p], p, clump_id[p]};
    }

    // Small lists are built by one thread (same result, no wake-up cost).
    const int nt = n >= 4096 ? std::max(1, threads) : 1;
    thread_i_.resize(nt);
    thread_j_.resize(nt);
    thread_found_.resize(nt);
    // Static chunks of particles per thread: each thread's pairs come out sorted by i,
    // so concatenating the threads in order gives the globally sorted list whatever nt.
#pragma omp parallel num_threads(nt)
    {
        const int t = omp_get_thread_num();
        const int chunk = (n + nt - 1) / nt;
        const int p_begin = std::min(n, t * chunk), p_end = std::min(n, p_begin + chunk);
        auto& li = thread_i_[t];
        auto& lj = thread_j_[t];
        li.clear();
        lj.clear();
        // A particle's candidates: at most every other particle.
        std::vector<int>& found = thread_found_[t];
        found.resize(n);
        for (int p = p_begin; p < p_end; ++p) {
            const long c = cell_of_[p];
            const long cx = c % nx, cy = (c / nx) % ny, cz = c / (nx * ny);
            int n_found = 0;
            const Vec3 xp = position[p];
            const double rp = radius[p];
            const int clump_p = clump_id[p];
            for (long dz = -1; dz <= 1; ++dz) {
                const long z = cz + dz;
                if (z < 0 || z >= nz) continue;
                for (long dy = -1; dy <= 1; ++dy) {
                    const long y = cy + dy;
                    if (y < 0 || y >= ny) continue;
                    for (long dx = -1; dx <= 1; ++dx) {
                        const long x = cx + dx;
                        if (x < 0 || x >= nx) continue;
                        const long cc = (z * ny + y) * nx + x;
                        // Branch-free: whether a member is a candidate (a later id, within
                        // reach, not of p's clump) is random from member to member. Each is
                        // written and kept only when it is one.
                        for (int k = cell_start_[cc]; k < cell_start_[cc + 1]; ++k) {
                            const CellMember& m = members_[k];
                            const double reach = rp + m.radius + skin;
                            const bool candidate = (m.id > p) & ((m.centre - xp).squaredNorm() < reach * reach) &
                                                   !(clump_p >= 0 && clump_p == m.clump);
                            found[n_found] = m.id;
                            n_found += candidate;
                        }
                    }
                }
            }
            std::sort(found.begin(), found.begin() + n_found);
            for (int e = 0; e < n_found; ++e) {
                li.push_back(p);
                lj.push_back(found[e]);
            }
        }
    }
    std::size_t total = 0;
    for (int t = 0; t < nt; ++t) total += thread_i_[t].size();
    pair_i.reserve(total);
    pair_j.reserve(total);
    for (int t = 0; t < nt; ++t) {
        pair_i.insert(pair_i.end(), thread_i_[t].begin(), thread_i_[t].end());
        pair_j.insert(pair_j.end(), thread_j_[t].begin(), thread_j_[t].end());
    }
}

}  // namespace triax
