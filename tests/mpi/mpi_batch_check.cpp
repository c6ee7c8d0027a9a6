// Run under `mpirun -np N` (N >= 1): the MPI batch against the threaded one, on the cheap
// analytic forward model (tests/diagnose), so the check takes seconds:
//   1. outcomes of a batch through MpiSimulationBatch equal ThreadSimulationBatch's bit for
//      bit (wire format), also with batches submitted from several threads at once;
//   2. a request whose run throws gives ok = false with the message, on whichever rank it
//      ran (a batch of only failing requests lands on every rank), and the job goes on;
//   3. a whole diagnosis through the ranks gives the same report JSON as the threaded one;
//   4. an empty batch and a batch smaller than the ranks return; shutdown ends every rank.
// A hang is caught by the ctest TIMEOUT. Exit 0 = all checks passed (rank 0 decides).
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tests/diagnose/analytic_triaxial_model.hpp"
#include "tests/diagnose/synthetic_lab.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "server/io/diagnosis_json.hpp"
#include "server/scaleout/mpi_simulation_batch.hpp"
#include "server/scaleout/mpi_task_pool.hpp"
#include "server/scaleout/wire_format.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;
using namespace triax::scaleout;

namespace {

constexpr std::uint64_t kFailingSeed = 13;

// The analytic model, except that seed 13 throws on every rank: a run that fails the way
// a DEM run does ("particle escaped the domain box").
class FailingAtSeed final : public ForwardModel {
public:
    std::vector<ParameterSpec> base_parameters() const override { return inner_.base_parameters(); }
    std::vector<ParameterSpec> effect_parameters(Effect e) const override { return inner_.effect_parameters(e); }
    LabDataset simulate(const ModelPoint& p, std::uint64_t seed) const override {
        if (seed == kFailingSeed) throw std::runtime_error("induced failure at seed 13");
        return inner_.simulate(p, seed);
    }

private:
    AnalyticTriaxialModel inner_;
};

int failures = 0;
void check(bool ok, const std::string& what) {
    if (!ok) {
        ++failures;
        std::fprintf(stderr, "FAILED: %s\n", what.c_str());
    }
}

std::vector<SimulationRequest> requests(int n, std::uint64_t seed0, bool with_failures) {
    std::vector<SimulationRequest> r;
    for (int i = 0; i < n; ++i) {
        ModelPoint p{{20e6 + 1e6 * i, 30.0 + 0.5 * i, 5.0 + 0.2 * i, 5e-4}, {}};
        if (i % 3 == 1) p.effects.push_back({Effect::RollingResistance, {0.05 * i}});
        const std::uint64_t seed = with_failures && i % 4 == 2 ? kFailingSeed : seed0 + static_cast<std::uint64_t>(i);
        r.push_back({p, seed});
    }
    return r;
}

void compare(const std::vector<SimulationOutcome>& got, const std::vector<SimulationOutcome>& want, const std::string& what) {
    check(got.size() == want.size(), what + ": one outcome per request");
    for (std::size_t i = 0; i < got.size() && i < want.size(); ++i)
        check(encode_outcome(got[i]) == encode_outcome(want[i]), what + ": outcome " + std::to_string(i) + " differs");
}

}  // namespace

int main(int argc, char** argv) {
    try {
        MpiSession session(argc, argv);
        MpiTaskPool pool;
        const FailingAtSeed model;
        if (!pool.is_root()) {
            MpiSimulationBatch::serve(pool, model);
            return 0;
        }
        MpiSimulationBatch batch(pool);
        ThreadSimulationBatch threads(2);
        check(batch.width() == pool.size(), "rank 0 computes too: width = ranks");

        // 1 + 2: one batch, with failures among the requests.
        const auto reqs = requests(12, 1, true);
        std::size_t done_calls = 0;
        const auto got = batch.run(model, reqs, [&](std::size_t) { ++done_calls; });
        compare(got, threads.run(model, reqs, {}), "mixed batch");
        check(done_calls == reqs.size(), "on_done once per request");
        for (std::size_t i = 0; i < reqs.size(); ++i) {
            const bool should_fail = reqs[i].seed == kFailingSeed;
            check(got[i].ok != should_fail, "request " + std::to_string(i) + " ok flag");
            if (should_fail) check(got[i].error == "induced failure at seed 13", "the worker's message comes back");
        }
        // Only failing requests, twice as many as ranks: some surely run on worker ranks.
        std::vector<SimulationRequest> bad(static_cast<std::size_t>(2 * pool.size()), {reqs[2].point, kFailingSeed});
        for (const auto& o : batch.run(model, bad, {})) check(!o.ok && o.error == "induced failure at seed 13", "failing batch");

        // 1: batches from several threads at once (the diagnosis's evaluation threads).
        std::vector<std::vector<SimulationOutcome>> par(3);
        std::vector<std::thread> callers;
        for (int t = 0; t < 3; ++t)
            callers.emplace_back([&, t] { par[static_cast<std::size_t>(t)] = batch.run(model, requests(5, 100 + 10 * t, t == 1), {}); });
        for (auto& c : callers) c.join();
        for (int t = 0; t < 3; ++t)
            compare(par[static_cast<std::size_t>(t)], threads.run(model, requests(5, 100 + 10 * t, t == 1), {}),
                    "concurrent batch " + std::to_string(t));

        // 4: empty and tiny batches.
        check(batch.run(model, {}, {}).empty(), "empty batch");
        compare(batch.run(model, requests(1, 7, false), {}), threads.run(model, requests(1, 7, false), {}), "one request");

        // 3: a whole diagnosis, threaded and through the ranks.
        const AnalyticTriaxialModel analytic;
        SyntheticLabOptions lo;
        lo.seed = 5;
        const LabDataset lab = make_synthetic_lab(analytic, {{30e6, 36.0, 10.0, 8e-4}, {{Effect::RollingResistance, {0.2}}}}, lo);
        DiagnoseOptions opt;
        opt.budget_runs = 8;
        opt.refine_runs = 3;
        opt.max_candidates = 2;
        opt.max_effects = 1;
        opt.concurrency = 3;
        DiagnoseObserver quiet;
        const auto threaded = triax::io::diagnosis_report_to_json(run_diagnosis(lab, analytic, opt, quiet)).dump(2);
        const auto ranked = triax::io::diagnosis_report_to_json(run_diagnosis(lab, analytic, opt, quiet, batch)).dump(2);
        check(threaded == ranked, "diagnosis report through the ranks equals the threaded one");

        pool.shutdown();
        std::fprintf(stderr, "mpi_batch_check: %d rank(s), %d failure(s)\n", pool.size(), failures);
        return failures == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mpi_batch_check: %s\n", e.what());
        return 1;
    }
}
