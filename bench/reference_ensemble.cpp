// The engine's statistical reference (tests/support/reference_ensemble.hpp): runs the
// reference ensemble's scheme for a range of packing seeds and prints each member's
// quantities, the ensemble's mean and spread, and (record=1) the table that
// tests/protocol/reference_ensemble_data.hpp stores. With check=1 the ensemble is judged
// against the stored reference exactly as the CI test judges its own seeds, so the false
// alarm rate of the contract can be measured on disjoint seed sets of the same build.
// Usage: reference_ensemble [seeds=101-124] [concurrency=2] [record=0] [check=0]
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bench/key_value_args.hpp"
#include "tests/protocol/reference_ensemble_data.hpp"
#include "tests/support/reference_ensemble.hpp"

using namespace triax::testing;

namespace {

bool parse_range(const std::string& s, std::uint64_t& from, std::uint64_t& to) {
    const auto dash = s.find('-');
    try {
        from = std::stoull(s.substr(0, dash));
        to = dash == std::string::npos ? from : std::stoull(s.substr(dash + 1));
    } catch (const std::exception&) {
        return false;
    }
    return from <= to && to - from < 1000;
}

}  // namespace

int main(int argc, char** argv) {
    std::map<std::string, std::string> kv{{"seeds", "101-124"}, {"concurrency", "2"}, {"record", "0"}, {"check", "0"}};
    if (!triax::bench::read_key_values(argc, argv, kv)) return 2;
    std::uint64_t from = 0, to = 0;
    if (!parse_range(kv["seeds"], from, to)) {
        std::fprintf(stderr, "seeds: expected FROM-TO, got '%s'\n", kv["seeds"].c_str());
        return 2;
    }
    const int concurrency = std::max(1, std::atoi(kv["concurrency"].c_str()));
    const std::size_t n = static_cast<std::size_t>(to - from + 1);
    std::vector<EnsembleSample> samples(n);
    std::vector<double> seconds(n);
    std::atomic<std::size_t> next{0};
    std::mutex print;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> team;
    for (int t = 0; t < concurrency; ++t)
        team.emplace_back([&] {
            for (std::size_t k = next++; k < n; k = next++) {
                const auto s0 = std::chrono::steady_clock::now();
                samples[k] = run_ensemble_member(from + k);
                seconds[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
                std::lock_guard<std::mutex> lock(print);
                std::fprintf(stderr, "seed %llu done in %.1f s\n", static_cast<unsigned long long>(from + k), seconds[k]);
            }
        });
    for (auto& t : team) t.join();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::printf("seed");
    for (const char* q : kEnsembleQuantities) std::printf("\t%s", q);
    std::printf("\tseconds\n");
    for (std::size_t k = 0; k < n; ++k) {
        std::printf("%llu", static_cast<unsigned long long>(from + k));
        for (double x : samples[k]) std::printf("\t%.6g", x);
        std::printf("\t%.1f\n", seconds[k]);
    }
    const EnsembleMoments m = ensemble_moments(samples);
    std::printf("mean");
    for (double x : m.mean) std::printf("\t%.6g", x);
    std::printf("\nstd");
    for (double x : m.std) std::printf("\t%.6g", x);
    std::printf("\n%zu members, %.1f s wall at concurrency %d\n", n, wall, concurrency);

    if (kv["record"] == "1") {
        std::printf("\n// paste into tests/protocol/reference_ensemble_data.hpp\n");
        std::printf("inline const EnsembleMoments kReferenceEnsemble = {\n    %zu,\n    {", n);
        for (std::size_t j = 0; j < kEnsembleQuantityCount; ++j) std::printf("%s%.17g", j ? ", " : "", m.mean[j]);
        std::printf("},\n    {");
        for (std::size_t j = 0; j < kEnsembleQuantityCount; ++j) std::printf("%s%.17g", j ? ", " : "", m.std[j]);
        std::printf("}};\n");
    }
    if (kv["check"] == "1") {
        const EnsembleMoments& ref = kReferenceEnsemble;
        bool pass = true;
        std::printf("\nagainst the stored reference (%d members):\nquantity\tshift_in_errors\tspread_ratio\n", ref.members);
        for (std::size_t j = 0; j < kEnsembleQuantityCount; ++j) {
            const double z = mean_shift_in_errors(m, ref, j), r = spread_ratio(m, ref, j);
            std::printf("%s\t%+.2f\t%.2f\n", kEnsembleQuantities[j], z, r);
            pass = pass && std::abs(z) <= kMeanBound && r <= kSingleSpreadFactor && r >= 1.0 / kSingleSpreadFactor;
        }
        const double g = geometric_mean_spread_ratio(m, ref);
        pass = pass && g <= kSpreadFactor && g >= 1.0 / kSpreadFactor;
        std::printf("geometric mean spread ratio %.2f\nverdict: %s\n", g, pass ? "within the contract" : "OUTSIDE the contract");
    }
    return 0;
}
