// Design + local-surrogate Levenberg-Marquardt calibration (algorithm in calibration.hpp).
#include "engine/diagnose/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>

namespace triax::diagnose {

namespace {

double rss_of(const std::vector<double>& r) {
    if (r.empty()) return std::numeric_limits<double>::infinity();
    double s = 0.0;
    for (double v : r) s += v * v;
    return std::isfinite(s) ? s : std::numeric_limits<double>::infinity();
}

Eigen::VectorXd clamp_unit(Eigen::VectorXd u) {
    for (Eigen::Index j = 0; j < u.size(); ++j) u[j] = std::clamp(u[j], 0.0, 1.0);
    return u;
}

// Gaussian-weighted least-squares Jacobian of the residual around point `c` from all runs.
Eigen::VectorXd as_eigen(const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
std::vector<double> as_std(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// Columns for the `active` coordinates only; profiled coordinates are the evaluator's
// optimum at each point, not free variables, and are left out of the regression.
Eigen::MatrixXd local_jacobian(const CalibrationResult& h, const Eigen::VectorXd& c, const std::vector<double>& rc,
                               double width, const std::vector<Eigen::Index>& active) {
    const auto& residuals = h.point_residuals;
    const Eigen::Index k = static_cast<Eigen::Index>(active.size());
    const Eigen::Index n = static_cast<Eigen::Index>(rc.size());
    Eigen::MatrixXd dtwd = Eigen::MatrixXd::Zero(k, k);
    Eigen::MatrixXd rwd = Eigen::MatrixXd::Zero(n, k);
    Eigen::VectorXd d(k);
    for (std::size_t i = 0; i < h.points.size(); ++i) {
        if (!std::isfinite(h.point_rss[i]) || residuals[i].size() != rc.size()) continue;
        for (Eigen::Index a = 0; a < k; ++a) d[a] = h.points[i][static_cast<std::size_t>(active[static_cast<std::size_t>(a)])] - c[active[static_cast<std::size_t>(a)]];
        const double dist2 = d.squaredNorm();
        if (dist2 == 0.0) continue;
        const double w = std::exp(-dist2 / (2.0 * width * width));
        if (w < 1e-8) continue;
        dtwd.noalias() += w * d * d.transpose();
        for (Eigen::Index a = 0; a < n; ++a) rwd.row(a).noalias() += (w * (residuals[i][a] - rc[a])) * d.transpose();
    }
    // Small ridge: directions no run has explored get a zero slope rather than noise.
    const double ridge = 1e-6 * std::max(dtwd.trace() / static_cast<double>(std::max<Eigen::Index>(k, 1)), 1e-12) + 1e-12;
    dtwd.diagonal().array() += ridge;
    return rwd * dtwd.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
}

}  // namespace

std::vector<UnitPoint> latin_hypercube(int points, int dimensions, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<UnitPoint> out(static_cast<std::size_t>(std::max(points, 0)), UnitPoint(static_cast<std::size_t>(dimensions)));
    std::vector<int> perm(static_cast<std::size_t>(std::max(points, 0)));
    for (int j = 0; j < dimensions; ++j) {
        std::iota(perm.begin(), perm.end(), 0);
        std::shuffle(perm.begin(), perm.end(), rng);
        for (int i = 0; i < points; ++i)
            out[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = (perm[static_cast<std::size_t>(i)] + uni(rng)) / points;
    }
    return out;
}

double to_parameter(const ParameterSpec& s, double u) {
    if (s.log_scale) return s.lower * std::pow(s.upper / s.lower, u);
    return s.lower + u * (s.upper - s.lower);
}

double to_unit(const ParameterSpec& s, double v) {
    if (s.upper == s.lower) return 0.0;
    if (s.log_scale) return std::clamp(std::log(v / s.lower) / std::log(s.upper / s.lower), 0.0, 1.0);
    return std::clamp((v - s.lower) / (s.upper - s.lower), 0.0, 1.0);
}

double parameter_derivative(const ParameterSpec& s, double u) {
    if (s.log_scale) return to_parameter(s, u) * std::log(s.upper / s.lower);
    return s.upper - s.lower;
}

CalibrationResult calibrate(const BatchEvaluator& evaluate, const CalibrationSettings& st,
                            const std::function<void(int)>& progress) {
    const Eigen::Index k = static_cast<Eigen::Index>(st.start.size());
    if (k == 0) throw std::invalid_argument("calibrate: no parameter to calibrate (empty start point)");
    CalibrationResult res;
    auto& residuals = res.point_residuals;
    std::size_t best = 0;
    if (st.history)
        for (std::size_t i = 0; i < st.history->points.size(); ++i) {
            if (st.history->points[i].size() != st.start.size() ||
                st.history->point_residuals.size() != st.history->points.size())
                throw std::invalid_argument("calibrate: history is from another parameter space");
            res.points.push_back(st.history->points[i]);
            res.point_rss.push_back(st.history->point_rss[i]);
            residuals.push_back(st.history->point_residuals[i]);
            if (res.point_rss.back() < res.point_rss[best]) best = res.points.size() - 1;
        }

    std::vector<Eigen::Index> active;
    for (Eigen::Index j = 0; j < k; ++j)
        if (st.profiled.size() != st.start.size() || !st.profiled[static_cast<std::size_t>(j)]) active.push_back(j);
    if (active.empty()) throw std::invalid_argument("calibrate: every coordinate is profiled, nothing to step");
    const Eigen::Index ka = static_cast<Eigen::Index>(active.size());

    auto run_batch = [&](const std::vector<Eigen::VectorXd>& batch) {
        if (batch.empty()) return;
        std::vector<UnitPoint> points;
        for (const auto& b : batch) points.push_back(as_std(b));
        auto out = evaluate(points);
        if (out.size() != batch.size() || points.size() != batch.size())
            throw std::logic_error("calibrate: evaluator returned the wrong batch size");
        for (std::size_t i = 0; i < batch.size(); ++i) {
            res.points.push_back(points[i]);
            res.point_rss.push_back(rss_of(out[i]));
            residuals.push_back(std::move(out[i]));
            if (res.point_rss.back() < res.point_rss[best]) best = res.points.size() - 1;
        }
        res.runs += static_cast<int>(batch.size());
        if (progress) progress(res.runs);
    };

    // Design: the start point first, so `best` starts there; then the space-filling part.
    // Profiled coordinates start at the start point's value (the evaluator moves them).
    const Eigen::VectorXd start = as_eigen(st.start);
    std::vector<Eigen::VectorXd> design{clamp_unit(start)};
    if (st.axial_design)
        for (Eigen::Index j : active) {
            Eigen::VectorXd p = start;
            p[j] = start[j] + (start[j] + st.initial_radius <= 1.0 ? st.initial_radius : -st.initial_radius);
            design.push_back(clamp_unit(p));
        }
    for (const auto& p : st.extra_design) {
        if (p.size() != st.start.size()) throw std::invalid_argument("calibrate: extra design point of the wrong dimension");
        design.push_back(clamp_unit(as_eigen(p)));
    }
    for (auto& p : latin_hypercube(st.design_runs, static_cast<int>(ka), st.seed)) {
        Eigen::VectorXd u = start;
        for (Eigen::Index a = 0; a < ka; ++a) u[active[static_cast<std::size_t>(a)]] = p[static_cast<std::size_t>(a)];
        design.push_back(u);
    }
    const std::size_t batch_size = static_cast<std::size_t>(std::max(1, st.batch));
    for (std::size_t a = 0; a < design.size(); a += batch_size * 4)
        run_batch({design.begin() + static_cast<long>(a),
                   design.begin() + static_cast<long>(std::min(design.size(), a + batch_size * 4))});

    double radius = st.initial_radius;
    const int budget = res.runs + std::max(0, st.refine_runs);
    static const double kDamping[] = {1e-3, 1e-1, 1.0, 10.0};
    int failed_batches = 0;  // consecutive batches without improvement
    int compass = 0;         // next compass probe: axis compass/2 % ka, sign by parity
    // Separation of two runs in the max-norm over the stepped coordinates.
    auto apart = [&](std::size_t a, std::size_t b) {
        double d = 0.0;
        for (Eigen::Index j : active)
            d = std::max(d, std::abs(res.points[a][static_cast<std::size_t>(j)] - res.points[b][static_cast<std::size_t>(j)]));
        return d;
    };
    while (res.runs < budget && radius > 1e-3 && std::isfinite(res.point_rss[best])) {
        // Starts of this batch's steps: the best run, then the best run of each other basin.
        std::vector<std::size_t> starts{best};
        if (st.local_starts > 1) {
            std::vector<std::size_t> order(res.points.size());
            std::iota(order.begin(), order.end(), std::size_t{0});
            std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return res.point_rss[a] < res.point_rss[b]; });
            for (std::size_t i : order) {
                if (static_cast<int>(starts.size()) >= st.local_starts) break;
                if (!std::isfinite(res.point_rss[i])) break;
                if (std::all_of(starts.begin(), starts.end(), [&](std::size_t s) { return apart(i, s) >= st.separation; }))
                    starts.push_back(i);
            }
        }
        struct Local {
            Eigen::VectorXd c, rc, g;
            Eigen::MatrixXd jtj;
            double scale = 1.0;
        };
        std::vector<Local> locals;
        for (std::size_t s : starts) {
            Local l;
            l.c = as_eigen(res.points[s]);
            l.rc = as_eigen(residuals[s]);
            const Eigen::MatrixXd J = local_jacobian(res, l.c, residuals[s], std::max(radius, 0.05), active);
            l.jtj = J.transpose() * J;
            l.g = J.transpose() * l.rc;
            l.scale = std::max(l.jtj.diagonal().maxCoeff(), 1e-12);
            locals.push_back(std::move(l));
        }
        const Eigen::VectorXd c = locals.front().c;
        std::vector<Eigen::VectorXd> batch;
        const std::size_t want = std::min<std::size_t>(batch_size, static_cast<std::size_t>(budget - res.runs));
        // After a failed batch, half of the batch (at least one run every other batch when
        // the batch is one run) goes to compass probes instead of surrogate steps.
        std::size_t probes = 0;
        if (failed_batches > 0) probes = want >= 2 ? want / 2 : (failed_batches % 2 == 1 ? 1 : 0);
        const std::size_t steps = want - probes;
        auto differs = [&](const Eigen::VectorXd& p) {
            for (const auto& q : res.points)
                if ((as_eigen(q) - p).norm() < 1e-9) return false;  // already run
            for (const auto& q : batch)
                if ((q - p).norm() < 1e-9) return false;
            return true;
        };
        for (std::size_t b = 0; b < steps; ++b) {
            // Steps go round the starts; each start's steps take the damping values in turn.
            const Local& l = locals[b % locals.size()];
            const std::size_t d = b / locals.size();
            Eigen::MatrixXd a = l.jtj;
            a.diagonal().array() += kDamping[d % 4] * (1.0 + static_cast<double>(d / 4)) * l.scale * 1e-2 +
                                    1e-9 * l.scale;
            Eigen::VectorXd step = -a.ldlt().solve(l.g);
            const double len = step.lpNorm<Eigen::Infinity>();
            if (len > radius) step *= radius / len;
            Eigen::VectorXd p = l.c;
            for (Eigen::Index j = 0; j < ka; ++j) p[active[static_cast<std::size_t>(j)]] += step[j];
            p = clamp_unit(p);
            if (!differs(p)) {  // stuck on the box boundary or repeated: probe a random direction
                std::mt19937_64 rng(st.seed + static_cast<std::uint64_t>(res.runs) * 7919u + b);
                std::normal_distribution<double> nd;
                for (Eigen::Index j : active) p[j] = l.c[j] + 0.5 * radius * nd(rng);
                p = clamp_unit(p);
            }
            batch.push_back(p);
        }
        for (std::size_t b = 0; b < probes; ++b) {
            // Compass probe; if the + side is against the bound, the - side instead.
            for (int tries = 0; tries < 2 * static_cast<int>(ka); ++tries, ++compass) {
                const Eigen::Index j = active[static_cast<std::size_t>((compass / 2) % ka)];
                Eigen::VectorXd p = c;
                p[j] += (compass % 2 == 0 ? radius : -radius);
                p = clamp_unit(p);
                if (differs(p)) {
                    batch.push_back(p);
                    ++compass;
                    break;
                }
            }
        }
        if (batch.empty()) break;
        const double before = res.point_rss[best];
        run_batch(batch);
        const bool improved = res.point_rss[best] < before * (1.0 - 1e-6);
        failed_batches = improved ? 0 : failed_batches + 1;
        // The radius shrinks only when the compass probes failed too (a surrogate step that
        // fails says little about the scale on a jagged objective).
        if (improved) radius = std::min(0.5, radius * 1.5);
        else if (probes > 0 || batch_size == 1) radius *= 0.5;
    }

    res.best = res.points[best];
    res.residual = residuals[best];
    res.rss = res.point_rss[best];
    if (std::isfinite(res.rss)) {
        // Full-width Jacobian: columns of profiled coordinates are zero here (the caller
        // fills them by finite differences, which cost nothing for them).
        const Eigen::MatrixXd Ja = local_jacobian(res, as_eigen(res.best), res.residual, std::max(radius, 0.1), active);
        Eigen::MatrixXd J = Eigen::MatrixXd::Zero(Ja.rows(), k);
        for (Eigen::Index a = 0; a < ka; ++a) J.col(active[static_cast<std::size_t>(a)]) = Ja.col(a);
        res.jacobian.assign(J.data(), J.data() + J.size());
    }
    return res;
}

std::vector<double> parameter_std(const std::vector<ParameterSpec>& specs, const CalibrationResult& r,
                                  double n_effective) {
    const Eigen::Index k = static_cast<Eigen::Index>(specs.size());
    std::vector<double> out(specs.size(), 0.0);
    const double n = static_cast<double>(r.residual.size());
    if (static_cast<Eigen::Index>(r.best.size()) != k || r.jacobian.size() != r.residual.size() * specs.size() ||
        n <= static_cast<double>(k))
        return out;
    const Eigen::Map<const Eigen::MatrixXd> J(r.jacobian.data(), static_cast<Eigen::Index>(r.residual.size()), k);
    const double s2 = r.rss / (n - static_cast<double>(k)) * (n / std::max(n_effective, 1.0));
    Eigen::MatrixXd jtj = J.transpose() * J;
    jtj.diagonal().array() += 1e-12 * std::max(jtj.trace(), 1e-12);
    const Eigen::MatrixXd cov = s2 * jtj.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
    for (Eigen::Index j = 0; j < k; ++j) {
        const auto& s = specs[static_cast<std::size_t>(j)];
        // An unidentified parameter is reported with its whole range as uncertainty.
        const double su = std::min(std::sqrt(std::max(cov(j, j), 0.0)), 1.0);
        out[static_cast<std::size_t>(j)] = std::min(su * std::abs(parameter_derivative(s, r.best[static_cast<std::size_t>(j)])),
                                                    std::abs(s.upper - s.lower));
    }
    return out;
}

}  // namespace triax::diagnose
