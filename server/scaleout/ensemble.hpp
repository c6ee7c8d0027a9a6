#pragma once
// Ensemble runs as scale-out tasks: one scheme at several seeds (packings). A member
// travels as bytes (task_runner.hpp): the seed in, the curves and the run's own regime
// flags (engine/protocol/creep_regime.hpp) out, so the members can run on threads or MPI
// ranks with the same result. The statistics over the members are the engine's
// (engine/diagnose/seed_ensemble.hpp), their files server/io/ensemble_json.hpp.
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "engine/diagnose/seed_ensemble.hpp"
#include "engine/protocol/test_scheme.hpp"
#include "server/scaleout/task_runner.hpp"

namespace triax::scaleout {

// Seeds "1-8", "3", "1,4,9-12": ascending, without repeats. Throws std::invalid_argument.
std::vector<std::uint64_t> parse_seed_list(std::string_view text);

// The task of one member and the handler that runs it (the whole protocol of `scheme`
// at the task's seed).
std::string member_task(std::uint64_t seed);
TaskHandler member_handler(const protocol::TestScheme& scheme);
// The same, stopping when `cancel_requested()` turns true: polled before a member starts
// and between the engine's increments (protocol::RunObserver::cancel_requested). A member
// so stopped throws MemberCancelled (its TaskResult is not ok).
struct MemberCancelled : std::runtime_error {
    MemberCancelled() : std::runtime_error("member cancelled") {}
};
TaskHandler member_handler(const protocol::TestScheme& scheme, std::function<bool()> cancel_requested);
// A task's result read back (a failed task: ok = false with its message).
diagnose::EnsembleMember member_from_result(std::uint64_t seed, const TaskResult& result);

}  // namespace triax::scaleout
