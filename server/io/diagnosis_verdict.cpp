// Verdict text of a diagnosis report (see diagnosis_verdict.hpp).
#include "server/io/diagnosis_verdict.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace triax::io {

using namespace triax::diagnose;

namespace {

std::string pct(double x) {
    std::ostringstream o;
    o.setf(std::ios::fixed);
    o.precision(1);
    o << 100.0 * x << " %";
    return o.str();
}

// A parameter value in the unit a lab form shows (kPa, MPa, mm) where the SI unit is known.
std::string lab_value(double v, const std::string& unit) {
    std::ostringstream o;
    o << std::setprecision(3);
    if (unit == "Pa") {
        if (v >= 1e6) o << v / 1e6 << " MPa";
        else o << v / 1e3 << " kPa";
    } else if (unit == "m") {
        o << v * 1e3 << " mm";
    } else {
        o << v;
        if (!unit.empty() && unit != "-") o << " " << unit;
    }
    return o.str();
}

}  // namespace

std::string diagnosis_verdict(const DiagnosisReport& r) {
    std::ostringstream v;
    v.setf(std::ios::fixed);
    v.precision(1);
    const double tol = r.noise.tolerance_nrmse;
    switch (r.outcome) {
        case Outcome::EffectFound: {
            v << r.chosen_effect << " explains the residual";
            for (const auto& e : r.effects)
                if (e != r.chosen_effect) v << " (with " << e << ")";
            v << ": NRMSE " << pct(r.nrmse_before) << " -> " << pct(r.nrmse_after) << ", delta BIC " << r.delta_bic_vs_base
              << " vs the calibrated base model";
            if (!r.runners_up.empty()) {
                auto next = std::min_element(r.runners_up.begin(), r.runners_up.end(),
                                             [](auto& a, auto& b) { return a.delta_bic < b.delta_bic; });
                v << "; next best " << next->effect << " is worse by " << next->delta_bic;
            }
            break;
        }
        case Outcome::NoEffectNeeded:
            v << "no effect needed: the calibrated base model fits within what a change of packing and the readings' "
                 "noise leave (NRMSE "
              << pct(r.nrmse_after) << ", tolerance " << pct(tol) << ")";
            break;
        case Outcome::Unexplained:
            v << "unexplained: remaining NRMSE " << pct(r.nrmse_after) << " (tolerance of a right model " << pct(tol) << ")";
            if (!r.worst_remaining.curve.empty())
                v << ", largest in " << r.worst_remaining.curve << " " << r.worst_remaining.phase << " ("
                  << pct(r.worst_remaining.nrmse) << ")";
            if (!r.effects.empty()) {
                v << "; partly helped by";
                for (std::size_t i = 0; i < r.effects.size(); ++i) v << (i ? ", " : " ") << r.effects[i];
                v << " (NRMSE " << pct(r.nrmse_before) << " before)";
            } else {
                v << "; no effect in the catalog lowers BIC by enough and beyond the noise floor";
            }
            break;
    }
    v << "; noise floor: packings " << pct(r.noise.model_nrmse) << " (" << r.noise.seeds << " seeds), lab readings "
      << pct(r.noise.lab_nrmse);
    if (r.noise.smallest_nameable_gain > 0.0)
        v << "; an effect had to lower the NRMSE by more than " << pct(r.noise.smallest_nameable_gain)
          << " (the spread of paired gains across packings) to be named";
    if (r.unreached_after > 0)
        v << "; " << r.unreached_after << " of " << static_cast<long>(r.n_readings)
          << " readings not reached by the model (counted apart from the misfit)";
    for (const auto& a : r.artefacts_below_threshold) v << "; " << a << " kept as a correction below the evidence threshold";
    for (const auto& d : r.artefacts_dropped) v << "; " << d << " dropped (does not lower BIC)";
    for (const auto& b : r.at_bounds)
        v << "; " << b.name << " at the " << (b.upper ? "upper" : "lower") << " bound of its prior (" << lab_value(b.value, b.unit)
          << ")";
    if (!r.not_testable.empty()) {
        v << "; not tested:";
        for (std::size_t i = 0; i < r.not_testable.size(); ++i)
            v << (i ? ", " : " ") << r.not_testable[i].effect << " (" << r.not_testable[i].reason << ")";
    }
    v << "; " << r.runs_used << " model runs";
    if (r.retried_runs > 0) v << ", " << r.retried_runs << " retried on another packing";
    if (r.failed_runs > 0) {
        v << ", " << r.failed_runs << " failed";
        if (!r.failure_messages.empty()) v << " (" << r.failure_messages.front() << ")";
    }
    return v.str();
}

}  // namespace triax::io
