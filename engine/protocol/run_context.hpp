#pragma once
// What every stage of the protocol reports into: the scheme it runs, the result it fills,
// the caller's observer and the run's progress clock (internal to engine/protocol).
#include <chrono>
#include <string>
#include <vector>

#include "engine/core/world.hpp"
#include "engine/protocol/run_observer.hpp"
#include "engine/protocol/test_result.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::protocol {

// The run's clock and the progress line: weights per phase of the whole run
// (generation and consolidation 0.1 each, shear 0.25, the creep stages 0.55 together).
class Progress {
public:
    Progress(RunObserver& o, int creep_stages);
    // phase: 0 consolidation, 1 shear, 2 + k creep stage k; fraction of that phase done.
    // Throws Cancelled when the observer asks to cancel.
    void report(const std::string& stage, int phase, double fraction);
    double elapsed() const;
    struct Cancelled {};

private:
    RunObserver& obs_;
    std::chrono::steady_clock::time_point start_;
    std::vector<double> weights_;
};

struct RunContext {
    const TestScheme& scheme;
    TestResult& result;
    RunObserver& observer;
    Progress& progress;
};

// The world's energy ledger as one sample (phase 0 consolidation, 1 shear, 2 + k creep).
EnergySample energy_sample(const World& w, int phase, double time_s);

}  // namespace triax::protocol
