// Kinds of test weighted by their packing scatter in the fit (fit_weights.hpp,
// docs/diagnosis.md section 2).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "analytic_triaxial_model.hpp"
#include "engine/diagnose/diagnosis.hpp"
#include "engine/diagnose/fit_weights.hpp"
#include "synthetic_lab.hpp"

using namespace triax::diagnose;
using namespace triax::diagnose::testing;

namespace {

NoiseFloor floor_of(std::vector<std::pair<std::string, double>> per_kind, double lab = 0.01) {
    NoiseFloor f;
    f.seeds = 3;
    f.lab_nrmse = lab;
    f.model_nrmse_per_kind = std::move(per_kind);
    return f;
}

double weight_of(const KindWeights& w, const std::string& kind) {
    for (const auto& [k, v] : w)
        if (k == kind) return v;
    return -1.0;
}

// The DEM base's creep in a stand-in: its creep holds creep more the nearer the specimen is
// to failure (creep per log-time grows e-fold per 2 deg of friction angle below 36 deg), it
// has no creep parameter of its own, and its creep stages scatter between packings by a
// factor up to e^`creep_scatter` (the shear curves not at all), as stages near failure do on ~200 grains.
class NearFailureCreepModel final : public ForwardModel {
public:
    explicit NearFailureCreepModel(double creep_scatter) : creep_scatter_(creep_scatter) {}
    std::vector<ParameterSpec> base_parameters() const override {
        auto p = inner_.base_parameters();
        p.pop_back();  // the stand-in's own creep coefficient
        return p;
    }
    std::vector<ParameterSpec> effect_parameters(Effect e) const override {
        return e == Effect::ContactCreepViscosity ? inner_.effect_parameters(e) : std::vector<ParameterSpec>{};
    }
    LabDataset simulate(const ModelPoint& p, std::uint64_t seed) const override {
        ModelPoint full = p;
        full.base.push_back(1e-4 * std::exp((36.0 - p.base.at(1)) / 2.0));
        LabDataset d = inner_.simulate(full, seed);
        // The packing's factor on the creep after each stage's loading: e^[-s, s].
        const double packing = std::exp(creep_scatter_ * (static_cast<double>(seed % 7) / 3.0 - 1.0));
        for (auto& c : d.curves)
            if (c.kind == CurveKind::Creep && !c.axial_strain.empty())
                for (double& e : c.axial_strain) e = c.axial_strain.front() + (e - c.axial_strain.front()) * packing;
        return d;
    }

private:
    AnalyticTriaxialModel inner_;
    double creep_scatter_;
};

DiagnosisReport diagnose_near_failure(double creep_scatter) {
    const NearFailureCreepModel model(creep_scatter);
    // Truth: 36 deg with contact creep of 0.6 % x S^2 that the base cannot give.
    const ModelPoint truth{{30e6, 36.0, 10.0}, {{Effect::ContactCreepViscosity, {0.006, 3000.0}}}};
    const LabDataset lab = make_synthetic_lab(model, truth, SyntheticLabOptions{});
    DiagnoseOptions opt = analytic_method_options();
    opt.max_effects = 1;
    opt.max_candidates = 1;
    DiagnoseObserver quiet;
    return run_diagnosis(lab, model, opt, quiet);
}

double base_friction_angle(const DiagnosisReport& r) {
    const auto it = std::find_if(r.base_parameters.begin(), r.base_parameters.end(),
                                 [](const FittedParameter& f) { return f.name == "friction_angle"; });
    REQUIRE(it != r.base_parameters.end());
    return it->value;
}

}  // namespace

TEST_CASE("kind weights: the least scattered kind keeps 1, the others 1/scatter; none when the kinds agree", "[diagnose][weights]") {
    CHECK(kind_weights(floor_of({{"shear", 0.06}})).empty());                     // one kind
    CHECK(kind_weights(floor_of({{"shear", 0.06}, {"creep", 0.10}})).empty());    // within 2x
    const auto w = kind_weights(floor_of({{"shear", 0.06}, {"creep", 0.75}}));
    CHECK(weight_of(w, "shear") == 1.0);
    CHECK(weight_of(w, "creep") == Approx(0.08));
    // A kind with (almost) no packing scatter counts as scattered as the lab readings or
    // kMinimumKindScatter: it cannot take all the weight for a scatter nobody measured.
    const auto z = kind_weights(floor_of({{"shear", 0.0}, {"creep", 0.5}}, 0.005));
    CHECK(weight_of(z, "creep") == Approx(kMinimumKindScatter / 0.5));
    CHECK(kind_weights(floor_of({{"shear", 0.0}, {"creep", 0.5}}, 0.4)).empty());  // the lab noise rules both
}

TEST_CASE("reading weights follow the layout; unweighting restores the readings and the unreached penalty", "[diagnose][weights]") {
    std::vector<ResidualSeries> layout(3);
    layout[0].label = "stress_strain@100kPa", layout[0].x = {0, 1, 2};
    layout[1].label = "creep-1@100kPa", layout[1].x = {0, 1};
    layout[2].label = "instant@100kPa", layout[2].x = {1};
    const auto w = reading_weights(layout, {{"shear", 1.0}, {"creep", 0.1}});
    CHECK(w == std::vector<double>{1.0, 1.0, 1.0, 0.1, 0.1, 0.1});
    CHECK(reading_weights(layout, {}).empty());
    std::vector<double> r{0.2, -0.3, kUnreachedPenalty, 0.05, kUnreachedPenalty, -0.7};
    std::vector<double> weighted = r;
    for (std::size_t i = 0; i < r.size(); ++i) weighted[i] *= w[i];
    const auto back = unweighted(weighted, w);
    for (std::size_t i = 0; i < r.size(); ++i) CHECK(back[i] == Approx(r[i]));
    CHECK(is_unreached(back[2]));
    CHECK(is_unreached(back[4]));
    CHECK(unweighted(r, {}) == r);
}

TEST_CASE("a base whose creep holds scatter between packings keeps the lab's strength instead of buying creep by weakening",
          "[diagnose][weights]") {
    // Without scatter the kinds are not weighted: the base weakens to mimic the creep it
    // lacks (the mechanism the weights remove).
    const DiagnosisReport plain = diagnose_near_failure(0.0);
    const DiagnosisReport scattered = diagnose_near_failure(3.0);
    INFO("friction angle: creep stages without packing scatter " << base_friction_angle(plain)
         << " deg, with scatter " << base_friction_angle(scattered) << " deg (truth 36)");
    CHECK(plain.fit_weights.empty());
    REQUIRE(!scattered.fit_weights.empty());
    CHECK(weight_of(scattered.fit_weights, "shear") == 1.0);
    CHECK(weight_of(scattered.fit_weights, "creep") < 0.5);
    CHECK(base_friction_angle(plain) < 35.0);
    CHECK(std::abs(base_friction_angle(scattered) - 36.0) < 1.0);
    // The errors are reported on the readings as they are: the base leaves the creep it lacks
    // (its creep curves weigh 0.09 in the fit, so weighted they would read under 10 %).
    const auto creep_error = std::find_if(scattered.error_before.begin(), scattered.error_before.end(),
                                          [](const PhaseError& e) { return e.curve.rfind("creep", 0) == 0 && e.phase == "all"; });
    REQUIRE(creep_error != scattered.error_before.end());
    CHECK(creep_error->nrmse > 0.1);
}
