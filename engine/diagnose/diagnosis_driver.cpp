// The steps of a diagnosis (see diagnosis_driver.hpp and docs/diagnosis.md).
#include "engine/diagnose/diagnosis_driver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "engine/diagnose/fit_weights.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/remaining_misfit.hpp"

namespace triax::diagnose {

DiagnosisDriver::DiagnosisDriver(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& opt,
                                 DiagnoseObserver& obs, SimulationBatch& batch)
    : opt_(opt), obs_(obs), eval_(lab, model, batch, opt.seed) {
    int physical = 0, artefacts = 0;
    for (const auto& [e, s] : eval_.effect_specs()) (is_test_artefact(e) ? artefacts : physical) += 1;
    const int k = static_cast<int>(eval_.base_specs().size());
    // Paired gains: per step the model without the candidates and each candidate that passes
    // BIC, on the noise floor's other packings; and the final model with and without each
    // artefact kept (the artefacts' paired gains, settle_artefacts).
    const int paired = (opt_.max_effects * (opt_.max_candidates + 1) + 1 + artefacts) * std::max(0, opt_.noise_seeds - 1);
    // The kinds' weights (weigh_kinds) cost a refinement and a second noise floor when the
    // data hold two kinds of test.
    bool shear = false, creep = false;
    for (const auto& s : eval_.layout()) (curve_kind(s.label) == "creep" ? creep : shear) = true;
    weighing_runs_ = shear && creep && opt_.noise_seeds > 1 ? opt_.refine_runs + opt_.noise_seeds - 1 : 0;
    planned_runs_ = opt_.budget_runs + std::max(0, opt_.noise_seeds - 1) + weighing_runs_ + 2 * (k + 2) +
                    opt_.max_effects * (physical + (opt_.max_candidates + 1) * std::max(opt_.refine_runs, 1)) + paired;
    eval_.on_run([this](int) { report_progress(); });
    for (const auto& [e, why] : eval_.not_offered()) rep_.not_testable.push_back({std::string(effect_name(e)), why});
    rep_.held_fixed = model.held_fixed();
}

void DiagnosisDriver::report_progress() {
    const double pct = std::min(99.0, 100.0 * static_cast<double>(eval_.runs()) / std::max(planned_runs_, 1));
    obs_.on_progress(pct, stage_);
}

std::vector<std::vector<double>> DiagnosisDriver::evaluate(const Variant& v, std::vector<UnitPoint>& batch, bool polish) {
    if (obs_.cancelled()) throw DiagnosisCancelled{};
    auto out = eval_.residuals(v, batch, polish);
    if (obs_.cancelled()) throw DiagnosisCancelled{};
    return out;
}

double DiagnosisDriver::nrmse_of(double rss) const { return std::sqrt(rss / static_cast<double>(eval_.readings())); }

Fit DiagnosisDriver::fit(const Variant& v, const UnitPoint& start, int design_runs, int refine_runs, bool axial,
                         const CalibrationResult* history, std::vector<UnitPoint> extra_design, int local_starts) {
    Fit f{v, eval_.specs_of(v), {}, 0.0};
    CalibrationSettings st;
    st.start = start;
    st.design_runs = design_runs;
    st.refine_runs = refine_runs;
    st.batch = std::max(1, opt_.batch_runs);  // not concurrency: the same report on any machine
    st.seed = opt_.seed;
    st.axial_design = axial;
    st.history = history;
    st.extra_design = std::move(extra_design);
    st.local_starts = local_starts;
    st.initial_radius = axial ? 0.15 : 0.25;
    st.profiled.assign(f.specs.size(), false);
    for (const auto& [j, e] : eval_.artefact_coordinates(v)) st.profiled[j] = true;
    f.cal = calibrate([&](std::vector<UnitPoint>& b) { return evaluate(v, b); }, st);
    return f;
}

// The variant v fitted from runs already made (no new engine run): every point of `source`
// mapped onto v's coordinates (shared parameters kept, the others nominal), artefacts
// polished, the best kept. Valid when v's physical part is source's.
Fit DiagnosisDriver::refit_free(const Variant& v, const Fit& source) {
    std::vector<UnitPoint> points;
    for (const auto& u : source.cal.points) points.push_back(eval_.project(source.variant, u, v));
    CalibrationResult h;
    if (!points.empty()) {
        auto r = evaluate(v, points);
        for (std::size_t i = 0; i < points.size(); ++i) {
            h.points.push_back(points[i]);
            h.point_rss.push_back(r[i].empty() ? std::numeric_limits<double>::infinity() : residual_sum_of_squares(r[i]));
            h.point_residuals.push_back(std::move(r[i]));
        }
    }
    const auto best = std::min_element(h.point_rss.begin(), h.point_rss.end()) - h.point_rss.begin();
    // A calibration with no new point: collects the history and fits the surrogate.
    return fit(v, h.points.empty() ? eval_.project(source.variant, source.cal.best, v) : h.points[static_cast<std::size_t>(best)],
               0, 0, false, &h);
}

// Replaces the surrogate Jacobian of a fit by forward differences at its optimum (k runs,
// step 0.03 of each parameter's range, taken inward from the bounds): the reported
// uncertainties must not depend on how the refinement happened to scatter its runs.
// With `artefacts_only` just the artefact columns are replaced (they cost no run).
void DiagnosisDriver::finite_difference_jacobian(Fit& f, bool artefacts_only) {
    const std::size_t k = f.cal.best.size(), n = f.cal.residual.size();
    if (f.cal.jacobian.size() != n * k) f.cal.jacobian.assign(n * k, 0.0);
    std::vector<std::size_t> cols;
    if (artefacts_only)
        for (const auto& [j, e] : eval_.artefact_coordinates(f.variant)) cols.push_back(j);
    else
        for (std::size_t j = 0; j < k; ++j) cols.push_back(j);
    if (cols.empty()) return;
    std::vector<UnitPoint> probes;
    std::vector<double> steps;
    for (std::size_t j : cols) {
        UnitPoint u = f.cal.best;
        const double h = u[j] + 0.03 <= 1.0 ? 0.03 : -0.03;
        u[j] += h;
        probes.push_back(u);
        steps.push_back(h);
    }
    const auto r = evaluate(f.variant, probes, false);
    std::vector<double> J = f.cal.jacobian;
    for (std::size_t c = 0; c < cols.size(); ++c) {
        if (r[c].size() != n) return;  // a failed probe: keep the surrogate Jacobian
        for (std::size_t i = 0; i < n; ++i) J[cols[c] * n + i] = (r[c][i] - f.cal.residual[i]) / steps[c];
    }
    f.cal.jacobian = std::move(J);
}

std::vector<FittedParameter> DiagnosisDriver::parameters_of(const Fit& f, double n_eff) const {
    const auto stds = parameter_std(f.specs, f.cal, n_eff);
    std::vector<FittedParameter> out;
    for (std::size_t j = 0; j < f.specs.size(); ++j)
        out.push_back({f.specs[j].name, f.specs[j].unit, to_parameter(f.specs[j], f.cal.best[j]), stds[j]});
    return out;
}

// 1. Base calibration with every test artefact profiled: each engine run is scored with the
//    artefacts at their best, so an artefact cannot pull the physical parameters away while
//    the calibration tries to mimic it.
Fit DiagnosisDriver::calibrate_base() {
    stage_ = "calibration";
    Variant artefacts;
    for (const auto& [e, specs] : eval_.effect_specs())
        if (is_test_artefact(e)) artefacts.effects.push_back(e);
    UnitPoint start = eval_.nominal_unit(eval_.base_specs());
    for (Effect e : artefacts.effects) start = eval_.extended(start, e);
    const int design = std::max(2, opt_.budget_runs / 2);
    Fit calib = fit(artefacts, start, design - 1, std::max(0, opt_.budget_runs - design), false);
    if (!std::isfinite(calib.cal.rss)) {
        std::string why = "every base-model run failed (" + std::to_string(eval_.failures()) + " failures";
        for (const auto& m : eval_.failure_messages()) why += "; " + m;
        throw std::runtime_error(why + "); check the scheme");
    }
    return calib;
}

// 2. The calibrated base on other packings: what a change of packing alone gives.
void DiagnosisDriver::measure_noise_floor(const Fit& base) {
    stage_ = "noise floor";
    std::vector<std::vector<double>> replicas{eval_.unweighted(base.cal.residual)};
    if (opt_.noise_seeds > 1) {
        std::vector<std::uint64_t> seeds;
        for (int k = 1; k < opt_.noise_seeds; ++k) seeds.push_back(opt_.seed + static_cast<std::uint64_t>(k));
        for (auto& r : eval_.replicates(base.variant, base.cal.best, seeds))
            replicas.push_back(r.empty() ? r : eval_.unweighted(std::move(r)));
    }
    rep_.noise = noise_floor(eval_.layout(), replicas);
}

// 2b. Kinds of test weighted by their packing scatter (fit_weights.hpp). When the noise
//     floor at the pooled fit's base finds the kinds' scatters far apart, every run so far is
//     re-scored with the weights (no new run), the base refined on the weighted misfit, and
//     the noise floor measured again at the new base (the tolerance's). The weights hold for
//     the rest of the diagnosis. Not recomputed from the second floor: the scatter is the
//     base's own, and a base that no longer stands near failure has quiet creep stages, so
//     weights from there would hand the fit back to the weakening that made them scatter.
Fit DiagnosisDriver::weigh_kinds(const Fit& base) {
    const KindWeights w = kind_weights(rep_.noise);
    if (w.empty()) return base;
    eval_.set_reading_weights(reading_weights(eval_.layout(), w));
    rep_.fit_weights = w;
    stage_ = "calibration";
    // The re-scored runs are the refinement's history, so its best is never worse than theirs.
    const Fit rescored = refit_free(base.variant, base);
    Fit weighted = fit(base.variant, rescored.cal.best, 0, opt_.refine_runs, false, &rescored.cal, {}, 2);
    measure_noise_floor(weighted);
    return weighted;
}

// 3. Physical effects, stepwise. The artefacts stay in every model as nuisance parameters
//    (profiled, free) while physical effects are tried, so no physical candidate is charged
//    for, or credited with, a seating offset or a membrane. `base_source` receives the base
//    refined with a candidate's budget (the runs of the model without physical effects).
Fit DiagnosisDriver::add_effects(Fit current, Fit& base_source) {
    bool first = true;
    int step = 0;
    for (int physical_step = 1; physical_step <= opt_.max_effects; ++physical_step) {
        stage_ = "signatures";
        std::vector<Effect> pool;
        for (const auto& [e, specs] : eval_.effect_specs())
            if (std::find(current.variant.effects.begin(), current.variant.effects.end(), e) == current.variant.effects.end())
                pool.push_back(e);
        if (std::none_of(pool.begin(), pool.end(), [](Effect e) { return !is_test_artefact(e); })) break;
        ++step;
        // The current model refined with the budget a candidate gets, so no candidate wins
        // merely by being calibrated longer; the signatures are taken at that point.
        Fit same = fit(current.variant, current.cal.best, 0, opt_.refine_runs, false, &current.cal);
        if (same.cal.rss > current.cal.rss) same = current;
        if (first) base_source = same;
        first = false;

        finite_difference_jacobian(same, true);
        std::vector<CandidateResult> cands;
        std::vector<std::pair<double, Effect>> ranked;
        std::map<Effect, UnitPoint> signature_start;
        for (Effect e : pool) {
            cands.push_back(signature_of(same, e, signature_start[e]));
            cands.back().step = step;
            if (!is_test_artefact(e)) ranked.emplace_back(cands.back().signature_score, e);
        }
        std::stable_sort(ranked.begin(), ranked.end(), [](auto& a, auto& b) { return a.first > b.first; });
        stage_ = "candidates";
        std::vector<Fit> fits;
        for (std::size_t i = 0; i < ranked.size() && static_cast<int>(i) < opt_.max_candidates; ++i) {
            const Effect e = ranked[i].second;
            auto& c = *std::find_if(cands.begin(), cands.end(), [&](auto& x) { return x.effect == effect_name(e); });
            if (ranked[i].first < 0.05) {
                c.note = "signature does not match the residual (score < 0.05)";
                continue;
            }
            fits.push_back(fit_candidate(same, e, &signature_start[e]));
        }
        for (auto& c : cands)
            if (c.note.empty() &&
                std::none_of(fits.begin(), fits.end(), [&](auto& f) { return effect_name(f.variant.effects.back()) == c.effect; }))
                c.note = "ranked below the top " + std::to_string(opt_.max_candidates);
        const int w = select(same, fits, cands, step);
        if (w < 0) return same;
        current = fits[static_cast<std::size_t>(w)];
    }
    return current;
}

// 4. Backward pass over the artefacts (free): an artefact stays in the final model if it
//    pays for its parameter at all (BIC lower with it); it is named only if it lowers BIC by
//    more than kArtefactBicThreshold, its paired gain across packings exceeds the gain's
//    spread and it lowers the misfit on every confining pressure (with one packing: lowers
//    BIC by more than the options' threshold and the NRMSE by more than a change of packing
//    does, or at least halves it). A membrane's q + k eps also bends a base whose curve shape merely differs
//    from the lab's (Duncan-Chang curves that harden to 15 %: 26.9 -> 19.2 % against a floor
//    of 17.9 %); on another packing that bend gains little, so it is not named.
Fit DiagnosisDriver::settle_artefacts(Fit current) {
    const std::size_t n = eval_.readings();
    auto without = [&](Effect e) {
        Variant v;
        for (Effect g : current.variant.effects)
            if (g != e) v.effects.push_back(g);
        return refit_free(v, current);
    };
    for (bool again = true; again;) {
        again = false;
        for (Effect e : current.variant.effects) {
            if (!is_test_artefact(e)) continue;
            Fit w = without(e);
            const double ne = effective_readings(current.cal.residual, eval_.ranges());
            if (bic(w.cal.rss, n, ne, w.specs.size()) <= bic(current.cal.rss, n, ne, current.specs.size())) {
                rep_.artefacts_dropped.emplace_back(effect_name(e));
                current = w;
                again = true;
                break;
            }
        }
    }
    // Each artefact kept is a step of its own: the final model against itself without it.
    // Its gain is paired as a candidate's is (select()): the final model with and without
    // the artefact, each at its own point, on the noise floor's packings; the mean gain
    // must exceed its spread across packings. A packing's stick-slip history is common to
    // both and cancels, so a seating offset or a membrane is seen under a packing floor far
    // larger than its gain; an artefact that only bends one packing's curve is not named.
    const double ne = effective_readings(current.cal.residual, eval_.ranges());
    int step = rep_.steps.empty() ? 0 : rep_.steps.back().step;
    std::vector<double> with_elsewhere;
    bool with_run = false;
    std::vector<double> series_confining;
    for (const auto& s : eval_.layout()) series_confining.push_back(s.confining_pa);
    for (Effect e : current.variant.effects) {
        if (!is_test_artefact(e)) continue;
        const Fit w = without(e);
        SelectionStep st;
        st.step = ++step;
        st.added = std::string(effect_name(e));
        st.nrmse_before = nrmse_of(w.cal.rss);
        st.nrmse_after = nrmse_of(current.cal.rss);
        st.delta_bic = bic(current.cal.rss, n, ne, current.specs.size()) - bic(w.cal.rss, n, ne, w.specs.size());
        st.n_effective = ne;
        st.gain_by_confining = gains_by_confining(eval_.unweighted(w.cal.residual), eval_.unweighted(current.cal.residual),
                                                  eval_.ranges(), series_confining);
        bool named = false;
        if (opt_.noise_seeds > 1) {
            // The packings measure the gain's noise; BIC (at the artefacts' bound) says
            // whether the gain is large against the misfit that remains: a correction standing
            // in for a shape the model lacks gains consistently on every packing too.
            if (!with_run) with_elsewhere = nrmse_on_other_packings(current), with_run = true;
            const std::vector<double> without_elsewhere = nrmse_on_other_packings(w);
            st.paired_gains = paired_gains(st.nrmse_before - st.nrmse_after, without_elsewhere, with_elsewhere);
            named = artefact_named(st.delta_bic, st.paired_gains, st.gain_by_confining);
        } else {
            const bool beyond_packing = st.nrmse_before - st.nrmse_after > rep_.noise.model_nrmse;
            const bool halves = st.nrmse_after <= 0.5 * st.nrmse_before;
            named = st.delta_bic < -opt_.bic_threshold && (beyond_packing || halves);
        }
        if (!named) rep_.artefacts_below_threshold.emplace_back(effect_name(e));
        rep_.steps.push_back(st);
    }
    return current;
}

namespace {

// Pooled NRMSE over the readings the model reached (residuals.hpp: is_unreached) and the
// count of the others.
std::pair<double, std::size_t> reached_nrmse(const std::vector<double>& r) {
    double ss = 0.0;
    std::size_t n = 0, unreached = 0;
    for (double x : r) {
        if (is_unreached(x)) {
            ++unreached;
            continue;
        }
        ss += x * x;
        ++n;
    }
    return {n ? std::sqrt(ss / static_cast<double>(n)) : 0.0, unreached};
}

}  // namespace

// 5. The report on one footing: n_eff from the final model's residual.
void DiagnosisDriver::report(const Fit& final_fit, const Fit& base_source) {
    Fit current = final_fit;
    const std::size_t n = eval_.readings();
    Fit base_final = refit_free(Variant{}, base_source);  // the calibrated base, no artefact
    const double n_eff = effective_readings(current.cal.residual, eval_.ranges());
    rep_.n_readings = static_cast<double>(n);
    rep_.n_effective = n_eff;
    stage_ = "uncertainty";
    finite_difference_jacobian(base_final, !opt_.finite_difference_uncertainty);
    if (!current.variant.effects.empty()) finite_difference_jacobian(current, !opt_.finite_difference_uncertainty);
    else current.cal.jacobian = base_final.cal.jacobian;
    rep_.base_parameters = parameters_of(base_final, n_eff);
    rep_.parameters = parameters_of(current, n_eff);
    // Errors on the readings as they are (no kind weights).
    const std::vector<double> before = eval_.unweighted(base_final.cal.residual), after = eval_.unweighted(current.cal.residual);
    rep_.error_before = phase_errors(eval_.layout(), before);
    rep_.error_after = phase_errors(eval_.layout(), after);
    std::tie(rep_.nrmse_before, rep_.unreached_before) = reached_nrmse(before);
    std::tie(rep_.nrmse_after, rep_.unreached_after) = reached_nrmse(after);
    rep_.delta_bic_vs_base =
        bic(current.cal.rss, n, n_eff, current.specs.size()) - bic(base_final.cal.rss, n, n_eff, base_final.specs.size());
    rep_.base_curves = eval_.curves(base_final.variant, base_final.cal.best);
    rep_.final_curves = eval_.curves(current.variant, current.cal.best);

    for (Effect e : current.variant.effects) {
        const std::string name(effect_name(e));
        const bool below = std::find(rep_.artefacts_below_threshold.begin(), rep_.artefacts_below_threshold.end(), name) !=
                           rep_.artefacts_below_threshold.end();
        if (!is_test_artefact(e) || !below) rep_.effects.push_back(name);
    }
    std::vector<std::vector<double>> gain_sets;
    for (const auto& c : rep_.candidates) gain_sets.push_back(c.paired_gains);
    for (const auto& st : rep_.steps) gain_sets.push_back(st.paired_gains);
    rep_.noise.smallest_nameable_gain = median_paired_spread(gain_sets);
    // The outcome: is what remains within what a right model on another packing leaves?
    const RemainingMisfit remaining = judge_remaining(rep_.error_after, rep_.nrmse_after, rep_.noise);
    rep_.worst_remaining = remaining.where;
    const bool unexplained = remaining.unexplained;
    if (unexplained) rep_.outcome = Outcome::Unexplained;
    else if (!rep_.effects.empty()) rep_.outcome = Outcome::EffectFound;
    else rep_.outcome = Outcome::NoEffectNeeded;
    rep_.chosen_effect = unexplained ? "unexplained" : "none";
    if (!unexplained) {
        for (Effect e : current.variant.effects)
            if (!is_test_artefact(e)) {
                rep_.chosen_effect = std::string(effect_name(e));
                break;
            }
        if (rep_.chosen_effect == "none" && !rep_.effects.empty()) rep_.chosen_effect = rep_.effects.front();
    }
    // Runners-up: the other candidates of the step that selected the headline effect.
    for (std::size_t k = 0; k < rep_.steps.size() && k < step_bics_.size(); ++k)
        if (!rep_.effects.empty() && rep_.steps[k].added == rep_.effects.front())
            for (const auto& [name, b] : step_bics_[k])
                if (name != rep_.effects.front()) rep_.runners_up.push_back({name, b - step_winner_bic_[k]});
    // Base parameters at the edge of their prior: the base is straining, and what it cannot
    // give may be missing physics or a prior too narrow for this material.
    const auto& bs = eval_.base_specs();
    for (std::size_t j = 0; j < bs.size() && j < current.cal.best.size(); ++j) {
        const double u = current.cal.best[j];
        if (u > 0.005 && u < 0.995) continue;
        rep_.at_bounds.push_back({bs[j].name, bs[j].unit, to_parameter(bs[j], u), u >= 0.995});
    }
    rep_.runs_used = eval_.runs();
    rep_.failed_runs = eval_.failures();
    rep_.retried_runs = eval_.retried();
    rep_.failure_messages = eval_.failure_messages();
}

DiagnosisReport DiagnosisDriver::run() {
    Fit base = calibrate_base();
    measure_noise_floor(base);
    base = weigh_kinds(base);
    Fit base_source = base;
    Fit current = add_effects(base, base_source);
    current = settle_artefacts(current);
    report(current, base_source);
    obs_.on_progress(100.0, "done");
    return rep_;
}

// Signature ranking at a given base point (no calibration): residual there, a forward-
// difference Jacobian (k runs), one run per physical effect.
std::vector<CandidateResult> DiagnosisDriver::rank_at(const std::vector<double>& base_values) {
    const auto& bs = eval_.base_specs();
    if (base_values.size() != bs.size())
        throw std::invalid_argument("rank_effects: expected " + std::to_string(bs.size()) + " base values, got " +
                                    std::to_string(base_values.size()));
    Fit at{Variant{}, bs, {}, 0.0};
    for (std::size_t j = 0; j < bs.size(); ++j) at.cal.best.push_back(to_unit(bs[j], base_values[j]));
    stage_ = "signatures";
    std::vector<UnitPoint> p0{at.cal.best};
    auto r0 = evaluate(at.variant, p0, false);
    if (r0[0].empty()) throw std::runtime_error("rank_effects: the model run at the given point failed");
    at.cal.residual = r0[0];
    at.cal.rss = residual_sum_of_squares(at.cal.residual);
    finite_difference_jacobian(at);
    std::vector<CandidateResult> out;
    for (const auto& [e, specs] : eval_.effect_specs()) {
        UnitPoint where;
        out.push_back(signature_of(at, e, where));
    }
    std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.signature_score > b.signature_score; });
    return out;
}

}  // namespace triax::diagnose
