// Candidate search of the diagnosis: how well an effect's signature matches the residual,
// where its fit starts, the fit itself and the choice between candidates
// (docs/diagnosis.md sections 3 and 4).
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "engine/diagnose/diagnosis_driver.hpp"
#include "engine/diagnose/model_selection.hpp"
#include "engine/diagnose/signature_score.hpp"
#include "engine/diagnose/residuals.hpp"

namespace triax::diagnose {

namespace {

// Below this share of the residual along its signature an effect is not worth fitting.
constexpr double kMinimumScore = 0.05;
// An effect that is off at its lower bound and fitted within this share of its range from
// it is not named: on a DEM model a change of a few % of a range moves q by 10-28 %
// (docs/diagnosis.md, noise floor), so a gain found there is a chance hit on the rough
// objective, not the effect.
constexpr double kMinimumSwitch = 0.1;

}  // namespace

// Score test of section 3 (signature_score.hpp) at the current fit.
double DiagnosisDriver::score_signature(const Fit& current, const std::vector<double>& with_effect) const {
    return signature_score(current.cal.residual, with_effect, current.cal.jacobian, eval_.layout());
}

// Points at which effect e's signature is taken: its parameters at their nominal; for an
// effect with several parameters each off at its lower bound, one point per parameter with
// the others off, because data may carry one mechanism without the other.
std::vector<UnitPoint> DiagnosisDriver::signature_points(const UnitPoint& current, Effect e) const {
    const auto& sp = eval_.effect_specs().at(e);
    const bool separable = sp.size() > 1 && std::all_of(sp.begin(), sp.end(), [](auto& p) { return p.lower_is_off; });
    if (!separable) return {eval_.extended(current, e)};
    std::vector<UnitPoint> out;
    for (std::size_t j = 0; j < sp.size(); ++j) {
        UnitPoint u = current;
        for (std::size_t q = 0; q < sp.size(); ++q) u.push_back(q == j ? to_unit(sp[q], sp[q].nominal) : 0.0);
        out.push_back(std::move(u));
    }
    return out;
}

// The effect's signature score at `current` (the best over its signature points) and the
// point that gave it, where a fit of the effect starts.
CandidateResult DiagnosisDriver::signature_of(const Fit& current, Effect e, UnitPoint& best_point) {
    Variant v = current.variant;
    v.effects.push_back(e);
    std::vector<UnitPoint> at = signature_points(current.cal.best, e);
    const auto r = evaluate(v, at, false);
    CandidateResult c;
    c.effect = std::string(effect_name(e));
    best_point = at.front();
    bool failed = false;
    for (std::size_t i = 0; i < at.size(); ++i) {
        if (r[i].empty()) {
            failed = true;
            continue;
        }
        const double score = score_signature(current, r[i]);
        if (score > c.signature_score || i == 0) c.signature_score = std::max(score, c.signature_score), best_point = at[i];
    }
    if (failed) c.note = "signature run failed";
    return c;
}

// Line search along a one-parameter effect: the effect at off, nominal and further on two
// lines (the current base, and the prior when `with_prior_line`); the minimum of a parabola
// of the RSS through each line's three runs is returned as a further probe. Every run here
// is cached for the fit that follows.
std::vector<UnitPoint> DiagnosisDriver::line_search_probes(const Variant& v, const UnitPoint& start,
                                                           const std::vector<UnitPoint>& probes, bool with_prior_line) {
    std::vector<UnitPoint> line = probes;
    line.push_back(start);
    const auto r = evaluate(v, line);
    const std::size_t q = start.size() - 1;
    auto rss_off = [&](const UnitPoint& u) {
        UnitPoint o = u;
        o[q] = 0.0;
        std::vector<UnitPoint> b{o};
        const auto ro = evaluate(v, b);  // the model without the effect: cached
        return ro[0].empty() ? std::numeric_limits<double>::infinity() : residual_sum_of_squares(ro[0]);
    };
    auto rss_of = [&](std::size_t i) {
        return r[i].empty() ? std::numeric_limits<double>::infinity() : residual_sum_of_squares(r[i]);
    };
    // (index of nominal, index of further) on each line: current base, prior.
    std::vector<std::pair<std::size_t, std::size_t>> lines{{line.size() - 1, 0}};
    if (with_prior_line) lines.emplace_back(2, 1);
    std::vector<UnitPoint> out;
    for (const auto& [i_nom, i_far] : lines) {
        const double x0 = 0.0, x1 = line[i_nom][q], x2 = line[i_far][q];
        const double f0 = rss_off(line[i_nom]), f1 = rss_of(i_nom), f2 = rss_of(i_far);
        if (!std::isfinite(f0 + f1 + f2) || x1 <= x0 || x2 <= x1) continue;
        // Divided differences: f = f0 + d1 x + a x (x - x1).
        const double d1 = (f1 - f0) / (x1 - x0), d2 = (f2 - f1) / (x2 - x1);
        const double a = (d2 - d1) / (x2 - x0);
        if (a <= 0.0) continue;
        const double xm = std::clamp(0.5 * (x1 - d1 / a), 0.5 * kMinimumSwitch, 1.0);
        if (std::abs(xm - x1) < 0.03 || std::abs(xm - x2) < 0.03) continue;
        UnitPoint p = line[i_nom];
        p[q] = xm;
        out.push_back(std::move(p));
    }
    return out;
}

// Every "off at the lower bound" parameter of the fit's last effect is within
// kMinimumSwitch of its range from off (false for effects without an off value).
bool DiagnosisDriver::barely_on(const Fit& f) const {
    if (f.variant.effects.empty()) return false;
    const auto& sp = eval_.effect_specs().at(f.variant.effects.back());
    const std::size_t at = f.cal.best.size() - sp.size();
    for (std::size_t q = 0; q < sp.size(); ++q)
        if (!sp[q].lower_is_off || f.cal.best[at + q] >= kMinimumSwitch) return false;
    return true;
}

// Fit of `same` + e. An effect whose parameters are all off at their lower bound is seeded
// with the runs of `same` (they are this model with the effect off), so only the effect's
// own direction needs new runs, plus probes: one further along the effect (a large lever
// against DEM noise) and two from the prior (the base optimum may have drifted to mimic the
// effect with other parameters, and the way back is a valley local steps rarely find).
Fit DiagnosisDriver::fit_candidate(const Fit& same, Effect e, const UnitPoint* signature_start) {
    Variant v = same.variant;
    v.effects.push_back(e);
    const auto& especs = eval_.effect_specs().at(e);
    const bool seeded = std::all_of(especs.begin(), especs.end(), [](auto& p) { return p.lower_is_off; });
    if (!seeded) return fit(v, eval_.extended(same.cal.best, e), 0, opt_.refine_runs, true);
    CalibrationResult h;
    for (std::size_t q = 0; q < same.cal.points.size(); ++q) {
        UnitPoint u = same.cal.points[q];
        u.insert(u.end(), especs.size(), 0.0);
        h.points.push_back(u);
        h.point_rss.push_back(same.cal.point_rss[q]);
        h.point_residuals.push_back(same.cal.point_residuals[q]);
    }
    UnitPoint start = signature_start ? *signature_start : eval_.extended(same.cal.best, e), further = start;
    for (std::size_t q = start.size() - especs.size(); q < start.size(); ++q)
        if (start[q] > 0.0) further[q] = std::min(1.0, start[q] + 0.4);  // an "off" parameter stays off
    const UnitPoint prior = eval_.nominal_unit(eval_.base_specs());
    UnitPoint restart = further, at_prior = start;
    std::copy(prior.begin(), prior.end(), restart.begin());
    std::copy(prior.begin(), prior.end(), at_prior.begin());
    std::vector<UnitPoint> probes{further, restart};
    if (at_prior != start) probes.push_back(at_prior);
    if (especs.size() == 1) {
        const auto more = line_search_probes(v, start, probes, at_prior != start);
        probes.insert(probes.end(), more.begin(), more.end());
    }
    return fit(v, start, 0, opt_.refine_runs, false, &h, std::move(probes), 1);
}

std::vector<double> DiagnosisDriver::nrmse_on_other_packings(const Fit& f) {
    std::vector<std::uint64_t> seeds;
    for (int k = 1; k < opt_.noise_seeds; ++k) seeds.push_back(opt_.seed + static_cast<std::uint64_t>(k));
    std::vector<double> out;
    for (const auto& r : eval_.replicates(f.variant, f.cal.best, seeds)) {
        double ss = 0.0;
        if (r.empty()) ss = eval_.unreached_sum_of_squares();
        for (double x : r) ss += x * x;
        out.push_back(nrmse_of(ss));
    }
    return out;
}

// Records a step's candidates and picks the winner (index in `fits`, or -1). One n_eff for
// all, from the best-fitting model's residual. A candidate wins only if it lowers BIC by
// more than the threshold AND its gain is beyond what a change of packing gives. That gain
// is paired: the step's model with and without the effect are run on the same packings
// (the calibration's and the noise floor's), and the mean of the per-packing gains in
// pooled NRMSE must exceed their standard deviation. The packing's own stick-slip history
// is common to both runs of a pair and cancels; an effect fitted to one packing's noise
// gains nothing on the others. With a single packing (noise_seeds 1) the gain must exceed
// the packing scatter of the misfit itself, the model_nrmse of the noise floor.
int DiagnosisDriver::select(Fit& same, std::vector<Fit>& fits, std::vector<CandidateResult>& cands, int step) {
    const std::size_t n = eval_.readings();
    const Fit* best_fit = &same;
    for (const auto& f : fits)
        if (f.cal.rss < best_fit->cal.rss) best_fit = &f;
    const double n_eff = effective_readings(best_fit->cal.residual, eval_.ranges());
    same.bic = bic(same.cal.rss, n, n_eff, same.specs.size());
    const double floor = rep_.noise.model_nrmse;
    std::vector<double> without_elsewhere;  // the step's model on the other packings, run once
    bool without_run = false;
    int winner = -1;
    std::vector<std::pair<std::string, double>> bics;
    for (std::size_t i = 0; i < fits.size(); ++i) {
        auto& f = fits[i];
        f.bic = std::isfinite(f.cal.rss) ? bic(f.cal.rss, n, n_eff, f.specs.size()) : std::numeric_limits<double>::infinity();
        auto& c = *std::find_if(cands.begin(), cands.end(), [&](auto& x) { return x.effect == effect_name(f.variant.effects.back()); });
        c.fitted = true;
        c.rss = f.cal.rss;
        c.nrmse = std::sqrt(f.cal.rss / static_cast<double>(n));
        c.bic = f.bic;
        c.delta_bic_vs_base = f.bic - same.bic;
        auto all = parameters_of(f, n_eff);
        c.parameters.assign(all.end() - static_cast<long>(eval_.effect_specs().at(f.variant.effects.back()).size()), all.end());
        bics.emplace_back(c.effect, f.bic);
        if (!(f.bic < same.bic - opt_.bic_threshold)) continue;
        if (barely_on(f)) {
            std::ostringstream why;
            why << "not named: fitted within " << 100.0 * kMinimumSwitch
                << " % of its range from off, the scale at which a DEM response is rough (a chance gain)";
            c.note = why.str();
            continue;
        }
        const double gain = std::sqrt(same.cal.rss / static_cast<double>(n)) - c.nrmse;
        if (opt_.noise_seeds > 1) {
            if (!without_run) without_elsewhere = nrmse_on_other_packings(same), without_run = true;
            const std::vector<double> with_elsewhere = nrmse_on_other_packings(f);
            c.paired_gains = paired_gains(gain, without_elsewhere, with_elsewhere);
            const PairedGainSummary g = summarise_paired_gains(c.paired_gains);
            if (!g.seen()) {
                std::ostringstream why;
                why.precision(3);
                why << "not named: on " << c.paired_gains.size() << " packings it lowers NRMSE by " << 100.0 * g.mean
                    << " % on average, not more than the spread of that gain between packings (" << 100.0 * g.spread
                    << " %)";
                c.note = why.str();
                continue;
            }
        } else if (gain <= floor) {
            std::ostringstream why;
            why.precision(3);
            why << "not named: lowers NRMSE by " << 100.0 * gain << " %, not more than a change of packing ("
                << 100.0 * floor << " %)";
            c.note = why.str();
            continue;
        }
        if (winner < 0 || f.bic < fits[static_cast<std::size_t>(winner)].bic) winner = static_cast<int>(i);
    }
    std::stable_sort(cands.begin(), cands.end(), [](auto& a, auto& b) {
        if (a.fitted != b.fitted) return a.fitted;
        return a.fitted ? a.bic < b.bic : a.signature_score > b.signature_score;
    });
    for (const auto& c : cands) obs_.on_candidate(c);
    rep_.candidates.insert(rep_.candidates.end(), cands.begin(), cands.end());
    SelectionStep st;
    st.step = step;
    st.nrmse_before = std::sqrt(same.cal.rss / static_cast<double>(n));
    st.nrmse_after = st.nrmse_before;
    st.n_effective = n_eff;
    step_bics_.push_back(bics);
    step_winner_bic_.push_back(winner >= 0 ? fits[static_cast<std::size_t>(winner)].bic : same.bic);
    if (winner >= 0) {
        const auto& w = fits[static_cast<std::size_t>(winner)];
        st.added = std::string(effect_name(w.variant.effects.back()));
        st.nrmse_after = std::sqrt(w.cal.rss / static_cast<double>(n));
        st.delta_bic = w.bic - same.bic;
    }
    rep_.steps.push_back(st);
    return winner;
}

}  // namespace triax::diagnose
