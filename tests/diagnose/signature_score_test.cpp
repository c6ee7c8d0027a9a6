// The score test that ranks effects (engine/diagnose/signature_score.hpp; docs/diagnosis.md
// section 3) on hand-made residuals: an effect whose evidence is in the creep curves scores
// there even when its change of the shear curves is noise-like, what the parameters already
// produce is projected out, and only the direction that lowers the residual counts.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "engine/diagnose/signature_score.hpp"

using namespace triax::diagnose;

namespace {

ResidualSeries series(const std::string& label, std::size_t n) {
    ResidualSeries s;
    s.label = label;
    for (std::size_t i = 0; i < n; ++i) s.x.push_back(static_cast<double>(i)), s.lab.push_back(0.0);
    return s;
}

}  // namespace

TEST_CASE("signature score: creep evidence is not out-scored by a noise-like change of the shear curves", "[diagnose][signature]") {
    const std::vector<ResidualSeries> layout{series("volumetric@100kPa", 50), series("creep-4@100kPa", 20)};
    std::vector<double> r, with;
    for (int i = 0; i < 50; ++i) {
        r.push_back(0.5 * std::sin(0.7 * i));                    // the base misses the shear curve
        with.push_back(r.back() + 0.5 * std::cos(1.3 * i + 0.4));  // the effect changes it at random
    }
    for (int i = 0; i < 20; ++i) {
        r.push_back(-0.2);                // the base creeps less than the lab
        with.push_back(-0.2 + 0.1);       // the effect makes it creep more
    }
    const double score = signature_score(r, with, {}, layout);
    CHECK(score == Approx(1.0).margin(1e-9));  // on the creep curves: entirely along the residual
    // Pooled over every reading (one kind only) it would have been small.
    std::vector<ResidualSeries> one_kind = layout;
    one_kind[1].label = "stress_strain@100kPa";
    const double pooled = signature_score(r, with, {}, one_kind);
    CHECK(pooled < 0.15);
    CHECK(pooled > 0.0);

    // A direction the parameters already produce is projected out: nothing left to score.
    std::vector<double> jacobian(70, 0.0);
    for (std::size_t i = 50; i < 70; ++i) jacobian[i] = 1.0;
    std::vector<double> creep_only = r;
    for (std::size_t i = 50; i < 70; ++i) creep_only[i] += 0.1;
    CHECK(signature_score(r, creep_only, jacobian, layout) < 1e-6);

    // An effect that moves away from the lab scores 0.
    std::vector<double> away = r;
    for (std::size_t i = 50; i < 70; ++i) away[i] -= 0.1;
    CHECK(signature_score(r, away, {}, layout) == 0.0);
}
