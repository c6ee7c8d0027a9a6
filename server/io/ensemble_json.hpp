#pragma once
// An ensemble of seeds (engine/diagnose/seed_ensemble.hpp) as files and answers, in lab
// units (kPa, %, min; compression positive): ensemble.json and the band tables
// shear_band.csv and creep_band.csv, written by `triax ensemble` and stored by
// POST /ensembles.
#include <string>

#include <nlohmann/json.hpp>

#include "engine/diagnose/seed_ensemble.hpp"

namespace triax::io {

// With `with_curves` the bands are included (the file); without, the summary printed on
// stdout.
nlohmann::json ensemble_to_json(const diagnose::EnsembleSummary& s, bool with_curves);
std::string shear_band_csv(const diagnose::EnsembleSummary& s);
std::string creep_band_csv(const diagnose::EnsembleSummary& s);

}  // namespace triax::io
