#pragma once
// The kind of a stage of lab readings that carries no kind column, read from the physics
// of the readings. q is in kPa (a held q must exceed 1 kPa); time and deformation only
// enter through ratios, so any clock and either strain or a length will do.
//
//  creep  q is load-controlled: it may ramp up over a short time (the loading step) and
//         then holds within 5 % while the deformation keeps growing in time. The loading
//         step deforms the specimen much faster than the creep that follows it.
//  shear  the axial strain is driven: it grows monotonically (at a steady rate when there
//         is a clock) while q rises, then may peak, soften or plateau.
// Anything else is ambiguous and the caller asks for a kind column; the reason names the
// readings that decided. The rules and their thresholds are listed in lab_stage_kind.cpp.
#include <cstddef>
#include <string>
#include <vector>

namespace triax::io {

struct StageReadings {
    std::vector<double> q;            // deviator stress [kPa], one value per reading, in reading order
    std::vector<double> time;         // same length, or empty when the stage has no clock
    std::vector<double> deformation;  // axial strain or deformation, same length, or empty
    std::vector<int> line;            // where each reading is, for the reasons (same length as q)
};

struct StageKind {
    enum class Verdict { Shear, Creep, Ambiguous };
    Verdict verdict = Verdict::Ambiguous;
    // Creep: the first reading of the held part. Readings before it are the loading ramp:
    // the stage's clock starts at hold_begin and its deformation counts from reading 0 (the
    // level before loading), so the ramp's deformation is the stage's instantaneous part.
    std::size_t hold_begin = 0;
    double held_q = 0.0;  // creep: median q of the held part
    std::string reason;   // what decided, or why nothing could
};

StageKind classify_stage(const StageReadings& r);

}  // namespace triax::io
