// The DEM loop cases of tests/diagnose (dem_loop_cases.hpp) over several lab/model packing
// pairs: hidden rolling resistance, the control and hidden grain crushing, each with the
// CI case's options, so a case is kept in CI only if it passes on every pair (a change of
// the last bits of a trajectory is a change of packing). Prints one line per case and pair
// (verdict, NRMSE before -> after, runs, wall, the rules it failed) and the pass count.
// Usage: dem_loop_packings [case=all|rolling|control|crushing] [pairs=7:11,13:17,19:23,29:31,37:41]
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench/key_value_args.hpp"
#include "tests/diagnose/dem_loop_cases.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {

struct Named {
    const char* name;
    CaseSpec (*spec)();
    std::vector<std::string> (*rules)(const Case&);
};

const Named kCases[] = {
    {"rolling", rolling_case, rolling_failures},
    {"control", control_case, control_failures},
    {"crushing", crushing_case, crushing_failures},
};

std::vector<std::pair<std::uint64_t, std::uint64_t>> parse_pairs(const std::string& s) {
    std::vector<std::pair<std::uint64_t, std::uint64_t>> out;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ',')) {
        const auto colon = item.find(':');
        if (colon == std::string::npos) return {};
        out.emplace_back(std::stoull(item.substr(0, colon)), std::stoull(item.substr(colon + 1)));
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::map<std::string, std::string> kv{{"case", "all"}, {"pairs", "7:11,13:17,19:23,29:31,37:41"}};
    if (!triax::bench::read_key_values(argc, argv, kv)) return 2;
    const auto pairs = parse_pairs(kv["pairs"]);
    if (pairs.empty()) {
        std::fprintf(stderr, "pairs: expected LAB:MODEL[,LAB:MODEL...], got '%s'\n", kv["pairs"].c_str());
        return 2;
    }
    std::printf("case\tlab:model\tverdict\tnrmse_before_pct\tnrmse_after_pct\truns\twall_s\tpass\tfailed rules\n");
    for (const auto& named : kCases) {
        if (kv["case"] != "all" && kv["case"] != named.name) continue;
        int passed = 0;
        for (const auto& [lab, model] : pairs) {
            CaseSpec cs = named.spec();
            cs.lab_seed = lab;
            cs.model_seed = model;
            const Case c = run_case(cs);
            const auto failed = named.rules(c);
            std::string why;
            for (const auto& f : failed) why += (why.empty() ? "" : "; ") + f;
            passed += failed.empty();
            std::printf("%s\t%llu:%llu\t%s\t%.1f\t%.1f\t%d\t%.0f\t%s\t%s\n", named.name, static_cast<unsigned long long>(lab),
                        static_cast<unsigned long long>(model), c.report.chosen_effect.c_str(),
                        100.0 * c.report.nrmse_before, 100.0 * c.report.nrmse_after, c.report.runs_used, c.seconds,
                        failed.empty() ? "yes" : "no", why.c_str());
            std::fflush(stdout);
        }
        std::printf("%s: %d of %zu pairs pass\n", named.name, passed, pairs.size());
    }
    return 0;
}
