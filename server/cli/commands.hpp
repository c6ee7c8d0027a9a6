#pragma once
// The `triax` commands beyond `run` (main.cpp dispatches) and the input files they share.
#include <string>

#include "engine/diagnose/lab_data.hpp"
#include "engine/protocol/test_scheme.hpp"

namespace triax::cli {

// A scheme file (JSON, scheme.schema.json); errors name the file and the field.
protocol::TestScheme read_scheme_file(const std::string& path);
// A lab file in any upload format (csv, gds, ags, json; `format` empty = guessed from the
// content); errors name the file, line and column.
diagnose::LabDataset read_lab_file(const std::string& path, const std::string& format);

// `triax diagnose --scheme S --dataset LAB [--format F] [--options O] [--out REPORT]`
int diagnose_command(int argc, char** argv);
// `triax ensemble --scheme S --seeds 1-8 [--out DIR] [--concurrency N] [--threads N] [--max-particles N]`
int ensemble_command(int argc, char** argv);

}  // namespace triax::cli
