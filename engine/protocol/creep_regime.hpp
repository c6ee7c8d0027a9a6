#pragma once
// The late behaviour of one creep stage, read from its translated curve the way a lab reads
// a creep curve: by the creep in equal slices of the stage (docs/creep.md, "Regime flags").

#include <algorithm>

#include "engine/protocol/test_result.hpp"

namespace triax::protocol {

// The smallest change of axial strain a reading can show: 0.01 mm, the resolution of the
// axial displacement reading (dial gauge or LVDT) of a large triaxial apparatus, on the
// paper's 200-mm specimen. Creep below it over a fifth of the stage is no creep to the
// lab: it can neither show a stage speeding up nor keep it from reading as settled.
inline constexpr double kReadingResolutionStrain = 0.01e-3 / 0.2;

struct CreepRegime {
    bool accelerating = false;  // tertiary: the creep rate passed a minimum and rose again
    bool converged = false;     // the last fifth holds < 10 % of the stage's creep
};

// Tertiary creep is the textbook one: the rate falls through primary creep to a minimum,
// then rises. The stage is read in fifths: it is accelerating when its last fifth creeps
// more than 1.3 x the slowest of fifths 2-4 (the first holds the primary creep; a stage
// fastest in its fourth fifth and still fast in its fifth is tertiary too) and more than
// 5 % of the stage's creep (so a converged stage's reading noise cannot raise the flag). It
// converged when its last fifth holds under 10 % of its creep. A stage that ruptured
// (`st.ruptured`: ran away, or collapsed, below) is accelerating by definition. Both flags
// read the last fifth against the reading resolution as well: a last fifth that creeps less
// than a reading can show is neither a tertiary stage nor an unsettled one.
inline CreepRegime classify_creep_regime(const CreepStageResult& st, double duration_s) {
    const double creep_part = st.final_deformation_m - st.instant_deformation_m;
    const CreepPoint* edge[6];  // the readings at the fifths' edges
    for (int i = 0; i <= 5; ++i) edge[i] = &reading_at(st, i * duration_s / 5.0);
    double fifth[5];
    for (int i = 0; i < 5; ++i) fifth[i] = edge[i + 1]->axial_deformation_m - edge[i]->axial_deformation_m;
    const double late = fifth[4];
    const double slowest_before = std::min({fifth[1], fifth[2], fifth[3]});
    const bool late_readable = edge[5]->axial_strain - edge[4]->axial_strain > kReadingResolutionStrain;
    CreepRegime r;
    r.accelerating = st.ruptured || (late_readable && late > 1.3 * std::max(slowest_before, 0.0) &&
                                     late > 0.05 * std::max(creep_part, 1e-12));
    r.converged = !r.accelerating && (creep_part <= 0.0 || late < 0.1 * creep_part || !late_readable);
    return r;
}

// Creep rupture by collapse: within one increment of physical time at constant load the
// specimen shortens by more than the stage's whole loading step did. The held load then has
// no static equilibrium near the current strain: the skeleton gave way (a shear band, a
// cascade of corroded bonds), which is how the paper's S = 0.8 specimens "develop toward the
// destruction". A lab stops the stage there; a DEM specimen driven on finds a new
// equilibrium several per cent of strain later (crushed, denser), and its quiet tail would
// read as converged creep (docs/creep.md, "Regime flags").
inline bool creep_collapse(double increment_deformation_m, double loading_deformation_m) {
    return loading_deformation_m > 0.0 && increment_deformation_m > loading_deformation_m;
}

}  // namespace triax::protocol
