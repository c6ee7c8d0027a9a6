// The broad phase (neighbor/cell_list.hpp) against the definition it implements: every pair
// i < j whose surfaces are closer than the skin, |x_j - x_i| < r_i + r_j + skin, except pairs
// of one clump, sorted by (i, j). Checked against an all-pairs search on polydisperse piles
// (radius ratio 5, so cells hold many small spheres), with clumps, with a far-flung sphere
// (the grid's cap makes the cells larger), and on 1 and 2 threads (the parallel search runs
// from 4,096 spheres).
#include "engine/neighbor/cell_list.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <utility>
#include <vector>

using namespace triax;

namespace cell_list_check {

struct Pile {
    std::vector<Vec3> position;
    std::vector<double> radius;
    std::vector<int> clump;
};

// n spheres of 1-5 mm at a solid fraction of roughly 0.4 in a box; every 50th pair of
// consecutive ids forms a clump.
Pile pile(int n, unsigned seed) {
    Pile p;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double side = 4e-3 * std::cbrt(static_cast<double>(n));
    for (int q = 0; q < n; ++q) {
        p.position.emplace_back(side * u(rng), side * u(rng), side * u(rng));
        p.radius.push_back(1e-3 * (1.0 + 4.0 * u(rng) * u(rng)));
        p.clump.push_back(q % 50 < 2 ? q / 50 : -1);
    }
    return p;
}

std::vector<std::pair<int, int>> all_pairs(const Pile& p, double skin) {
    std::vector<std::pair<int, int>> pairs;
    const int n = static_cast<int>(p.position.size());
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            if (p.clump[i] >= 0 && p.clump[i] == p.clump[j]) continue;
            const double reach = p.radius[i] + p.radius[j] + skin;
            if ((p.position[j] - p.position[i]).squaredNorm() < reach * reach) pairs.emplace_back(i, j);
        }
    return pairs;
}

std::vector<std::pair<int, int>> cell_pairs(const Pile& p, double skin, int threads) {
    CellList cells;
    std::vector<int> pi, pj;
    cells.build(p.position, p.radius, p.clump, skin, threads, pi, pj);
    std::vector<std::pair<int, int>> pairs;
    for (std::size_t k = 0; k < pi.size(); ++k) pairs.emplace_back(pi[k], pj[k]);
    return pairs;
}

TEST_CASE("cell list: the candidate pairs are those of the all-pairs search, sorted", "[engine][neighbor]") {
    for (const int n : {300, 5000})
        for (const unsigned seed : {1u, 2u}) {
            Pile p = pile(n, seed);
            INFO(n << " spheres, seed " << seed);
            const double skin = 0.1e-3;
            const auto expected = all_pairs(p, skin);
            REQUIRE(expected.size() > static_cast<std::size_t>(n) / 2);
            CHECK(cell_pairs(p, skin, 1) == expected);
            CHECK(cell_pairs(p, skin, 2) == expected);
            // One sphere far away: the grid's cap enlarges the cells; the pairs stay the same.
            p.position[n / 2] = Vec3(5.0, -3.0, 7.0);
            const auto far = all_pairs(p, skin);
            CHECK(cell_pairs(p, skin, 1) == far);
            CHECK(cell_pairs(p, skin, 2) == far);
        }
}

}  // namespace cell_list_check
