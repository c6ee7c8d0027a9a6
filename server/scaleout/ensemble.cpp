#include "server/scaleout/ensemble.hpp"

#include <algorithm>
#include <stdexcept>

#include "engine/protocol/run_observer.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/scaleout/wire_format.hpp"

namespace triax::scaleout {

std::vector<std::uint64_t> parse_seed_list(std::string_view text) {
    std::vector<std::uint64_t> out;
    auto number = [&](std::string_view s) -> std::uint64_t {
        if (s.empty() || s.find_first_not_of("0123456789") != std::string_view::npos || s.size() > 18)
            throw std::invalid_argument("--seeds: '" + std::string(s) + "' is not a seed (a number >= 0)");
        return std::stoull(std::string(s));
    };
    std::size_t at = 0;
    while (at <= text.size()) {
        const auto comma = std::min(text.find(',', at), text.size());
        const auto part = text.substr(at, comma - at);
        const auto dash = part.find('-');
        const std::uint64_t lo = number(part.substr(0, dash));
        const std::uint64_t hi = dash == std::string_view::npos ? lo : number(part.substr(dash + 1));
        if (hi < lo) throw std::invalid_argument("--seeds: range '" + std::string(part) + "' runs backwards");
        if (hi - lo >= 10000 || out.size() + (hi - lo) >= 10000) throw std::invalid_argument("--seeds: more than 10000 seeds");
        for (std::uint64_t s = lo; s <= hi; ++s) out.push_back(s);
        at = comma + 1;
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::string member_task(std::uint64_t seed) {
    WireWriter w;
    w.u64(seed);
    return w.take();
}

namespace {

// A member's result bytes: q_f, strain at failure, the shear curve, then per creep stage
// its number, stress level, regime flags and translated curve.
std::string encode_member(const protocol::TestResult& r, std::uint64_t seed) {
    if (r.shear.empty()) throw std::runtime_error("the run did not shear (seed " + std::to_string(seed) + ")");
    WireWriter w;
    w.f64(r.q_failure_pa);
    w.f64(r.axial_strain_at_failure);
    std::vector<double> e, q, v;
    for (const auto& p : r.shear) e.push_back(p.axial_strain), q.push_back(p.q_pa), v.push_back(p.volumetric_strain);
    w.doubles(e);
    w.doubles(q);
    w.doubles(v);
    w.u64(r.creep_stages.size());
    for (const auto& st : r.creep_stages) {
        w.u64(static_cast<std::uint64_t>(st.stage));
        w.f64(st.stress_level);
        w.u64((st.accelerating ? 1u : 0u) | (st.converged ? 2u : 0u) | (st.ruptured ? 4u : 0u));
        std::vector<double> t, a;
        for (const auto& p : st.translated) t.push_back(p.time_s), a.push_back(p.axial_strain);
        w.doubles(t);
        w.doubles(a);
    }
    return w.take();
}

// Passes the caller's cancel poll to the engine; ignores everything else.
class CancelPoll final : public protocol::RunObserver {
public:
    explicit CancelPoll(const std::function<bool()>& poll) : poll_(poll) {}
    bool cancel_requested() override { return poll_(); }

private:
    const std::function<bool()>& poll_;
};

}  // namespace

TaskHandler member_handler(const protocol::TestScheme& scheme) {
    return [scheme](std::string_view task) {
        WireReader rd(task);
        protocol::TestScheme s = scheme;
        s.seed = rd.u64("seed");
        return encode_member(protocol::run_triaxial_test(s), s.seed);
    };
}

TaskHandler member_handler(const protocol::TestScheme& scheme, std::function<bool()> cancel_requested) {
    return [scheme, cancel = std::move(cancel_requested)](std::string_view task) {
        WireReader rd(task);
        protocol::TestScheme s = scheme;
        s.seed = rd.u64("seed");
        if (cancel()) throw MemberCancelled();
        CancelPoll observer(cancel);
        const auto r = protocol::run_triaxial_test(s, observer);
        if (r.cancelled) throw MemberCancelled();
        return encode_member(r, s.seed);
    };
}

diagnose::EnsembleMember member_from_result(std::uint64_t seed, const TaskResult& result) {
    diagnose::EnsembleMember m;
    m.seed = seed;
    if (!result.ok) {
        m.error = result.bytes;
        return m;
    }
    try {
        WireReader rd(result.bytes);
        m.q_failure_pa = rd.f64("q_f");
        m.axial_strain_at_failure = rd.f64("strain at failure");
        m.axial_strain = rd.doubles("axial strain");
        m.deviator_pa = rd.doubles("deviator");
        m.volumetric_strain = rd.doubles("volumetric strain");
        const auto n = rd.u64("creep stages");
        for (std::uint64_t k = 0; k < n && k < 1000; ++k) {
            diagnose::MemberStage st;
            st.stage = static_cast<int>(rd.u64("stage"));
            st.stress_level = rd.f64("stress level");
            const auto flags = rd.u64("regime");
            st.accelerating = flags & 1u, st.converged = flags & 2u, st.ruptured = flags & 4u;
            st.time_s = rd.doubles("creep time");
            st.axial_strain = rd.doubles("creep strain");
            m.stages.push_back(std::move(st));
        }
        if (!rd.done()) throw std::runtime_error("wire format: bytes left after the member");
        m.ok = true;
    } catch (const std::exception& e) {
        m = diagnose::EnsembleMember{};
        m.seed = seed;
        m.error = e.what();
    }
    return m;
}

}  // namespace triax::scaleout
