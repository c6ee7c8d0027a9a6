// The loop: calibrate the base model, rank the catalog by residual signature, fit the best
// candidates as augmented models, select by BIC, report. Algorithm: docs/diagnosis.md.
#include "engine/diagnose/diagnosis.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <Eigen/Dense>

#include "engine/diagnose/calibration.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/residuals.hpp"
#include "engine/diagnose/test_artefacts.hpp"

namespace triax::diagnose {

namespace {

// Below this share of the residual along its signature an effect is not worth fitting.
constexpr double kMinimumScore = 0.05;

// A model variant: the base plus a list of effects; parameters laid out base first.
struct Variant {
    std::vector<Effect> effects;
};

struct Fit {
    Variant variant;
    std::vector<ParameterSpec> specs;
    CalibrationResult cal;
    double bic = 0.0;
};

class Loop {
public:
    Loop(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& opt, DiagnoseObserver& obs)
        : model_(model), opt_(opt), obs_(obs), layout_(residual_layout(lab)), ranges_(series_ranges(layout_)),
          base_specs_(model.base_parameters()) {
        if (base_specs_.empty()) throw std::invalid_argument("forward model has no base parameter to calibrate");
        for (Effect e : kAllEffects) {
            if (model.includes(e)) continue;
            auto specs = is_test_artefact(e) ? artefact_parameters(e) : model.effect_parameters(e);
            if (!specs.empty()) effect_specs_[e] = std::move(specs);
        }
        int physical = 0;
        for (const auto& [e, s] : effect_specs_) physical += is_test_artefact(e) ? 0 : 1;
        planned_runs_ = opt_.budget_runs + 2 * static_cast<int>(base_specs_.size() + 2) +
                        opt_.max_effects * (physical + (opt_.max_candidates + 1) * std::max(opt_.refine_runs, 1));
    }

    DiagnosisReport run();
    std::vector<CandidateResult> rank_at(const std::vector<double>& base_values);

private:
    std::vector<ParameterSpec> specs_of(const Variant& v) const {
        auto s = base_specs_;
        for (Effect e : v.effects) s.insert(s.end(), effect_specs_.at(e).begin(), effect_specs_.at(e).end());
        return s;
    }

    // Predicted dataset at unit-cube point u: one engine run per distinct physical point
    // (cached, so artefact-only changes cost nothing), then the artefacts as post-processing.
    LabDataset predict(const Variant& v, const UnitPoint& u) {
        const auto specs = specs_of(v);
        std::vector<double> values(specs.size());
        for (std::size_t j = 0; j < specs.size(); ++j) values[j] = to_parameter(specs[j], u[j]);
        ModelPoint point;
        point.base.assign(values.begin(), values.begin() + static_cast<long>(base_specs_.size()));
        std::vector<std::pair<Effect, std::vector<double>>> artefacts;
        std::size_t at = base_specs_.size();
        for (Effect e : v.effects) {
            const std::size_t m = effect_specs_.at(e).size();
            std::vector<double> p(values.begin() + static_cast<long>(at), values.begin() + static_cast<long>(at + m));
            at += m;
            (is_test_artefact(e) ? artefacts : point.effects).emplace_back(e, std::move(p));
        }
        std::sort(point.effects.begin(), point.effects.end());
        std::vector<double> key = point.base;
        for (const auto& [e, p] : point.effects) {
            key.push_back(1000.0 + static_cast<double>(e));
            key.insert(key.end(), p.begin(), p.end());
        }
        LabDataset predicted;
        bool hit = false;
        {
            std::lock_guard<std::mutex> lock(cache_mutex_);
            auto it = cache_.find(key);
            if (it != cache_.end()) predicted = it->second, hit = true;
        }
        if (!hit) {
            predicted = model_.simulate(point, opt_.seed);
            std::lock_guard<std::mutex> lock(cache_mutex_);
            cache_.emplace(key, predicted);
            ++runs_;
        }
        for (const auto& [e, p] : artefacts) apply_test_artefact(predicted, e, p);
        return predicted;
    }

    std::vector<double> residual_at(const Variant& v, const UnitPoint& u) {
        return normalised_residual(layout_, predict(v, u));
    }

    // Independent evaluations spread over opt.concurrency threads; a failed run gives an
    // empty residual (the calibration treats it as infinitely bad).
    std::vector<std::vector<double>> evaluate(const Variant& v, const std::vector<UnitPoint>& batch) {
        if (obs_.cancelled()) throw DiagnosisCancelled{};
        std::vector<std::vector<double>> out(batch.size());
        std::atomic<std::size_t> next{0};
        auto worker = [&] {
            for (std::size_t i; (i = next.fetch_add(1)) < batch.size();) {
                try {
                    out[i] = residual_at(v, batch[i]);
                } catch (const std::exception&) {
                    out[i].clear();
                    failures_.fetch_add(1);
                }
            }
        };
        const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(opt_.concurrency, 1)), batch.size());
        std::vector<std::thread> pool;
        for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (auto& t : pool) t.join();
        report_progress();
        return out;
    }

    void report_progress() {
        const double pct = std::min(99.0, 100.0 * static_cast<double>(runs_) / std::max(planned_runs_, 1));
        obs_.on_progress(pct, stage_);
        if (obs_.cancelled()) throw DiagnosisCancelled{};
    }

    Fit fit(const Variant& v, const UnitPoint& start, int design_runs, int refine_runs, bool axial,
            const CalibrationResult* history = nullptr) {
        Fit f{v, specs_of(v), {}, 0.0};
        CalibrationSettings st;
        st.start = start;
        st.design_runs = design_runs;
        st.refine_runs = refine_runs;
        st.batch = std::max(1, opt_.concurrency);
        st.seed = opt_.seed;
        st.axial_design = axial;
        st.history = history;
        st.initial_radius = axial ? 0.15 : 0.25;
        f.cal = calibrate([&](const std::vector<UnitPoint>& b) { return evaluate(v, b); }, st);
        return f;
    }

    UnitPoint nominal_unit(const std::vector<ParameterSpec>& specs) const {
        UnitPoint u(specs.size());
        for (std::size_t j = 0; j < specs.size(); ++j) u[j] = to_unit(specs[j], specs[j].nominal);
        return u;
    }

    UnitPoint extended(UnitPoint u, Effect e) const {
        const UnitPoint extra = nominal_unit(effect_specs_.at(e));
        u.insert(u.end(), extra.begin(), extra.end());
        return u;
    }

    // Replaces the surrogate Jacobian of a fit by forward differences at its optimum (k runs,
    // step 0.03 of each parameter's range, taken inward from the bounds): the reported
    // uncertainties must not depend on how the refinement happened to scatter its runs.
    void finite_difference_jacobian(Fit& f) {
        const std::size_t k = f.cal.best.size(), n = f.cal.residual.size();
        std::vector<UnitPoint> probes;
        std::vector<double> steps;
        for (std::size_t j = 0; j < k; ++j) {
            UnitPoint u = f.cal.best;
            const double h = u[j] + 0.03 <= 1.0 ? 0.03 : -0.03;
            u[j] += h;
            probes.push_back(u);
            steps.push_back(h);
        }
        const auto r = evaluate(f.variant, probes);
        std::vector<double> J(n * k, 0.0);
        for (std::size_t j = 0; j < k; ++j) {
            if (r[j].size() != n) return;  // a failed probe: keep the surrogate Jacobian
            for (std::size_t i = 0; i < n; ++i) J[j * n + i] = (r[j][i] - f.cal.residual[i]) / steps[j];
        }
        f.cal.jacobian = std::move(J);
    }

    std::vector<FittedParameter> parameters_of(const Fit& f, double n_eff) const {
        const auto stds = parameter_std(f.specs, f.cal, n_eff);
        std::vector<FittedParameter> out;
        for (std::size_t j = 0; j < f.specs.size(); ++j)
            out.push_back({f.specs[j].name, f.specs[j].unit, to_parameter(f.specs[j], f.cal.best[j]),
                           stds[j]});
        return out;
    }

    double score_signature(const Fit& current, const std::vector<double>& with_effect) const;

    const ForwardModel& model_;
    const DiagnoseOptions& opt_;
    DiagnoseObserver& obs_;
    std::vector<ResidualSeries> layout_;
    std::vector<std::pair<std::size_t, std::size_t>> ranges_;
    std::vector<ParameterSpec> base_specs_;
    std::map<Effect, std::vector<ParameterSpec>> effect_specs_;
    std::map<std::vector<double>, LabDataset> cache_;
    std::mutex cache_mutex_;
    std::atomic<int> failures_{0};
    int runs_ = 0;
    int planned_runs_ = 1;
    std::string stage_ = "calibration";
};

// Score test: how much of the current residual lies along the effect's signature once the
// directions the current parameters can already produce (columns of J) are projected out.
// Only the direction that reduces the residual counts (effects are switched on from zero).
double Loop::score_signature(const Fit& current, const std::vector<double>& with_effect) const {
    const auto& r0 = current.cal.residual;
    if (with_effect.size() != r0.size()) return 0.0;
    const Eigen::Index n = static_cast<Eigen::Index>(r0.size());
    Eigen::VectorXd s(n), r(n);
    for (Eigen::Index i = 0; i < n; ++i) s[i] = with_effect[static_cast<std::size_t>(i)] - r0[static_cast<std::size_t>(i)], r[i] = r0[static_cast<std::size_t>(i)];
    const Eigen::Index k = static_cast<Eigen::Index>(current.cal.best.size());
    if (k > 0 && static_cast<Eigen::Index>(current.cal.jacobian.size()) == n * k) {
        const Eigen::Map<const Eigen::MatrixXd> J(current.cal.jacobian.data(), n, k);
        Eigen::MatrixXd jtj = J.transpose() * J;
        jtj.diagonal().array() += 1e-9 * std::max(jtj.trace(), 1e-12);
        s -= J * jtj.ldlt().solve(J.transpose() * s);
    }
    const double denom = s.norm() * r.norm();
    if (denom <= 0.0) return 0.0;
    return std::max(0.0, -r.dot(s) / denom);
}

DiagnosisReport Loop::run() {
    DiagnosisReport rep;
    const std::size_t n = layout_.empty() ? 0 : ranges_.back().second;

    // 1. Base calibration: space-filling design then local refinement.
    stage_ = "calibration";
    const int design = std::max(2, opt_.budget_runs / 2);
    Fit base = fit(Variant{}, nominal_unit(base_specs_), design - 1, std::max(0, opt_.budget_runs - design), false);
    if (!std::isfinite(base.cal.rss))
        throw std::runtime_error("every base-model run failed (" + std::to_string(failures_.load()) +
                                 " failures); check the scheme");

    Fit current = base;
    Fit base_final = base;
    // Per step: BIC of each fitted candidate, and of the step's winner, for runners-up.
    std::vector<std::vector<std::pair<std::string, double>>> step_bics;
    std::vector<double> step_winner_bic;

    for (int step = 1; step <= opt_.max_effects; ++step) {
        // 2. Signatures of the effects not yet in the model, at the current optimum.
        stage_ = "signatures";
        std::vector<Effect> pool;
        for (const auto& [e, specs] : effect_specs_)
            if (std::find(current.variant.effects.begin(), current.variant.effects.end(), e) == current.variant.effects.end())
                pool.push_back(e);
        if (pool.empty()) break;
        std::vector<CandidateResult> cands;
        std::vector<std::pair<double, Effect>> ranked;
        for (Effect e : pool) {
            Variant v = current.variant;
            v.effects.push_back(e);
            auto r = evaluate(v, {extended(current.cal.best, e)});
            CandidateResult c;
            c.step = step;
            c.effect = std::string(effect_name(e));
            c.signature_score = r[0].empty() ? 0.0 : score_signature(current, r[0]);
            if (r[0].empty()) c.note = "signature run failed";
            ranked.emplace_back(c.signature_score, e);
            cands.push_back(c);
        }
        std::stable_sort(ranked.begin(), ranked.end(), [](auto& a, auto& b) { return a.first > b.first; });

        // 3. The current model refined with the same run budget a candidate gets, so no
        //    candidate wins merely by being calibrated longer.
        stage_ = "candidates";
        Fit same = fit(current.variant, current.cal.best, 0, opt_.refine_runs, false, &current.cal);
        if (same.cal.rss > current.cal.rss) same = current;

        std::vector<Fit> fits;
        for (std::size_t i = 0; i < ranked.size() && static_cast<int>(i) < opt_.max_candidates; ++i) {
            auto& c = *std::find_if(cands.begin(), cands.end(), [&](auto& x) { return x.effect == effect_name(ranked[i].second); });
            if (ranked[i].first < kMinimumScore) {
                c.note = "signature does not match the residual (score < 0.05)";
                continue;
            }
            Variant v = current.variant;
            v.effects.push_back(ranked[i].second);
            // Refinement from the current optimum: axial probes then local steps.
            fits.push_back(fit(v, extended(same.cal.best, ranked[i].second), 0, opt_.refine_runs, true));
        }
        for (auto& c : cands)
            if (c.note.empty() && std::none_of(fits.begin(), fits.end(), [&](auto& f) { return effect_name(f.variant.effects.back()) == c.effect; }))
                c.note = "ranked below the top " + std::to_string(opt_.max_candidates);

        // 4. BIC with one n_eff for all: from the best-fitting model's residual.
        const Fit* best_fit = &same;
        for (const auto& f : fits)
            if (f.cal.rss < best_fit->cal.rss) best_fit = &f;
        const double n_eff = effective_readings(best_fit->cal.residual, ranges_);
        same.bic = bic(same.cal.rss, n, n_eff, same.specs.size());
        const Fit* winner = nullptr;
        std::vector<std::pair<std::string, double>> bics;
        for (auto& f : fits) {
            f.bic = std::isfinite(f.cal.rss) ? bic(f.cal.rss, n, n_eff, f.specs.size()) : std::numeric_limits<double>::infinity();
            auto& c = *std::find_if(cands.begin(), cands.end(), [&](auto& x) { return x.effect == effect_name(f.variant.effects.back()); });
            c.fitted = true;
            c.rss = f.cal.rss;
            c.nrmse = std::sqrt(f.cal.rss / static_cast<double>(n));
            c.bic = f.bic;
            c.delta_bic_vs_base = f.bic - same.bic;
            auto all = parameters_of(f, n_eff);
            c.parameters.assign(all.end() - static_cast<long>(effect_specs_.at(f.variant.effects.back()).size()), all.end());
            bics.emplace_back(c.effect, f.bic);
            if (f.bic < same.bic - opt_.bic_threshold && (!winner || f.bic < winner->bic)) winner = &f;
        }
        std::stable_sort(cands.begin(), cands.end(), [](auto& a, auto& b) {
            if (a.fitted != b.fitted) return a.fitted;
            return a.fitted ? a.bic < b.bic : a.signature_score > b.signature_score;
        });
        for (const auto& c : cands) obs_.on_candidate(c);
        rep.candidates.insert(rep.candidates.end(), cands.begin(), cands.end());
        SelectionStep st;
        st.step = step;
        st.nrmse_before = std::sqrt(same.cal.rss / static_cast<double>(n));
        st.n_effective = n_eff;
        if (step == 1) base_final = same;
        step_bics.push_back(bics);
        step_winner_bic.push_back(winner ? winner->bic : same.bic);
        if (!winner) {
            st.nrmse_after = st.nrmse_before;
            rep.steps.push_back(st);
            current = same;
            break;
        }
        st.added = std::string(effect_name(winner->variant.effects.back()));
        st.nrmse_after = std::sqrt(winner->cal.rss / static_cast<double>(n));
        st.delta_bic = winner->bic - same.bic;
        rep.steps.push_back(st);
        current = *winner;
    }

    // 5. Report on one footing: n_eff from the final model's residual.
    const double n_eff = effective_readings(current.cal.residual, ranges_);
    const double bic_base = bic(base_final.cal.rss, n, n_eff, base_final.specs.size());
    const double bic_final = bic(current.cal.rss, n, n_eff, current.specs.size());
    rep.n_readings = static_cast<double>(n);
    rep.n_effective = n_eff;
    stage_ = "uncertainty";
    finite_difference_jacobian(base_final);
    if (!current.variant.effects.empty()) finite_difference_jacobian(current);
    else current.cal.jacobian = base_final.cal.jacobian;
    rep.base_parameters = parameters_of(base_final, n_eff);
    rep.parameters = parameters_of(current, n_eff);
    rep.error_before = phase_errors(layout_, base_final.cal.residual);
    rep.error_after = phase_errors(layout_, current.cal.residual);
    rep.nrmse_before = std::sqrt(base_final.cal.rss / static_cast<double>(n));
    rep.nrmse_after = std::sqrt(current.cal.rss / static_cast<double>(n));
    rep.delta_bic_vs_base = bic_final - bic_base;
    for (Effect e : current.variant.effects) rep.effects.emplace_back(effect_name(e));
    // The missing physics is the headline; artefacts found alongside stay in `effects`.
    for (Effect e : current.variant.effects)
        if (!is_test_artefact(e)) {
            rep.chosen_effect = std::string(effect_name(e));
            break;
        }
    if (rep.chosen_effect == "unexplained" && !rep.effects.empty()) rep.chosen_effect = rep.effects.front();
    // Runners-up: the other candidates of the step that selected the chosen effect.
    for (std::size_t k = 0; k < rep.steps.size(); ++k)
        if (rep.steps[k].added == rep.chosen_effect)
            for (const auto& [name, b] : step_bics[k])
                if (name != rep.chosen_effect) rep.runners_up.push_back({name, b - step_winner_bic[k]});
    rep.runs_used = runs_;

    std::ostringstream v;
    v.setf(std::ios::fixed);
    v.precision(1);
    if (rep.effects.empty()) {
        const PhaseError* worst = nullptr;
        for (const auto& e : rep.error_after)
            if (e.phase != "all" && e.n >= 3 && (!worst || e.nrmse > worst->nrmse)) worst = &e;
        v << "unexplained: no effect in the catalog lowers BIC by more than " << opt_.bic_threshold
          << " (n_eff = " << n_eff << " of " << n << " readings); remaining NRMSE " << 100.0 * rep.nrmse_after << " %";
        if (worst) v << ", largest in " << worst->curve << " " << worst->phase << " (" << 100.0 * worst->nrmse << " %)";
    } else {
        v << rep.chosen_effect << " explains the residual";
        for (const auto& e : rep.effects)
            if (e != rep.chosen_effect) v << " (with " << e << ")";
        v << ": delta BIC " << rep.delta_bic_vs_base << " vs the calibrated base model, NRMSE " << 100.0 * rep.nrmse_before
          << " % -> " << 100.0 * rep.nrmse_after << " %";
        if (!rep.runners_up.empty()) {
            auto next = std::min_element(rep.runners_up.begin(), rep.runners_up.end(),
                                         [](auto& a, auto& b) { return a.delta_bic < b.delta_bic; });
            v << "; next best " << next->effect << " is worse by " << next->delta_bic;
        }
    }
    v << "; " << runs_ << " model runs";
    if (failures_ > 0) v << " (" << failures_.load() << " failed)";
    rep.verdict = v.str();
    obs_.on_progress(100.0, "done");
    return rep;
}

// Signature ranking at a given base point (no calibration): residual there, a forward-
// difference Jacobian (k runs), one run per physical effect.
std::vector<CandidateResult> Loop::rank_at(const std::vector<double>& base_values) {
    if (base_values.size() != base_specs_.size())
        throw std::invalid_argument("rank_effects: expected " + std::to_string(base_specs_.size()) + " base values, got " +
                                    std::to_string(base_values.size()));
    Fit at{Variant{}, base_specs_, {}, 0.0};
    for (std::size_t j = 0; j < base_specs_.size(); ++j) at.cal.best.push_back(to_unit(base_specs_[j], base_values[j]));
    stage_ = "signatures";
    auto r0 = evaluate(at.variant, {at.cal.best});
    if (r0[0].empty()) throw std::runtime_error("rank_effects: the model run at the given point failed");
    at.cal.residual = r0[0];
    at.cal.rss = residual_sum_of_squares(at.cal.residual);
    finite_difference_jacobian(at);
    std::vector<CandidateResult> out;
    for (const auto& [e, specs] : effect_specs_) {
        Variant v;
        v.effects.push_back(e);
        auto r = evaluate(v, {extended(at.cal.best, e)});
        CandidateResult c;
        c.effect = std::string(effect_name(e));
        c.signature_score = r[0].empty() ? 0.0 : score_signature(at, r[0]);
        if (r[0].empty()) c.note = "signature run failed";
        out.push_back(c);
    }
    std::stable_sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.signature_score > b.signature_score; });
    return out;
}

}  // namespace

std::vector<CandidateResult> rank_effects(const LabDataset& lab, const ForwardModel& model,
                                          const std::vector<double>& base_values, const DiagnoseOptions& options,
                                          DiagnoseObserver& observer) {
    Loop loop(lab, model, options, observer);
    return loop.rank_at(base_values);
}

DiagnosisReport run_diagnosis(const LabDataset& lab, const ForwardModel& model, const DiagnoseOptions& options,
                              DiagnoseObserver& observer) {
    if (options.budget_runs < 4) throw std::invalid_argument("budget_runs must be at least 4, got " + std::to_string(options.budget_runs));
    if (options.refine_runs < 1) throw std::invalid_argument("refine_runs must be at least 1");
    if (options.max_effects < 1) throw std::invalid_argument("max_effects must be at least 1");
    Loop loop(lab, model, options, observer);
    return loop.run();
}

}  // namespace triax::diagnose
