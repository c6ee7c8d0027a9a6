#pragma once
// The sentence a lab engineer reads for a diagnosis, written from the report's data (the
// engine returns data only). Lab units; NRMSE as % of each lab curve's range.
#include <string>

#include "engine/diagnose/diagnosis.hpp"

namespace triax::io {

std::string diagnosis_verdict(const diagnose::DiagnosisReport& report);

}  // namespace triax::io
