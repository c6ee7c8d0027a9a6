// The score test of an effect's signature (see signature_score.hpp).
#include "engine/diagnose/signature_score.hpp"

#include <algorithm>

#include <Eigen/Dense>

#include "engine/diagnose/noise_floor.hpp"

namespace triax::diagnose {

namespace {

// `negligible`: a signature left this small by the projection is rounding, not a direction.
double share_along(const Eigen::VectorXd& r, const Eigen::VectorXd& s, double negligible) {
    const double denom = s.norm() * r.norm();
    return denom > 0.0 && s.norm() > negligible ? std::max(0.0, -r.dot(s) / denom) : 0.0;
}

}  // namespace

double signature_score(const std::vector<double>& residual, const std::vector<double>& with_effect,
                       const std::vector<double>& jacobian, const std::vector<ResidualSeries>& layout) {
    if (with_effect.size() != residual.size() || residual.empty()) return 0.0;
    const Eigen::Index n = static_cast<Eigen::Index>(residual.size());
    Eigen::VectorXd s(n), r(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        s[i] = with_effect[k] - residual[k];
        r[i] = residual[k];
    }
    const double negligible = 1e-6 * s.norm();  // the ridge below leaves ~1e-9 of a produced direction
    const Eigen::Index k = static_cast<Eigen::Index>(jacobian.size()) / n;
    if (k > 0 && static_cast<Eigen::Index>(jacobian.size()) == n * k) {
        const Eigen::Map<const Eigen::MatrixXd> J(jacobian.data(), n, k);
        Eigen::MatrixXd jtj = J.transpose() * J;
        jtj.diagonal().array() += 1e-9 * std::max(jtj.trace(), 1e-12);
        s -= J * jtj.ldlt().solve(J.transpose() * s);
    }
    double score = share_along(r, s, negligible);
    // Each kind of test apart: an effect whose evidence is in the creep curves is not
    // out-scored by its incidental change of the shear curves, which a different trajectory
    // on the same packing makes noise-like (an outside creep set: contact creep scored 0.02
    // pooled, its volumetric residual 3.8 % of strain against creep stages of 0.006-0.25 %).
    const auto ranges = series_ranges(layout);
    for (const char* kind : {"shear", "creep"}) {
        std::vector<Eigen::Index> at;
        for (std::size_t c = 0; c < layout.size(); ++c)
            if (curve_kind(layout[c].label) == kind)
                for (std::size_t i = ranges[c].first; i < ranges[c].second && i < residual.size(); ++i)
                    at.push_back(static_cast<Eigen::Index>(i));
        if (at.empty() || static_cast<Eigen::Index>(at.size()) == n) continue;
        const Eigen::Index m = static_cast<Eigen::Index>(at.size());
        Eigen::VectorXd rk(m), sk(m);
        for (Eigen::Index i = 0; i < m; ++i) rk[i] = r[at[static_cast<std::size_t>(i)]], sk[i] = s[at[static_cast<std::size_t>(i)]];
        score = std::max(score, share_along(rk, sk, negligible));
    }
    return score;
}

}  // namespace triax::diagnose
