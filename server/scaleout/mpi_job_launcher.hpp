#pragma once
// A diagnosis of the service run as an MPI job: the inputs are written into the job's
// directory, `mpirun --hostfile H -np N <triax> diagnose ...` is started as a child process,
// its stderr lines drive the job's progress and candidate events, and its report file is
// read back. Cancel (the observer's flag, polled every 0.25 s) ends the child's process
// group: SIGTERM, then SIGKILL after 5 s. No MPI library is needed here, only mpirun.
//
// The child's stderr protocol (server/cli/scaleout_commands.cpp):
//   progress <percent> <stage>
//   candidate <one-line JSON, io::candidate_to_json>
// every other line (mpirun's own messages, errors) is kept for the failure message.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagnose/diagnosis.hpp"

namespace triax::scaleout {

struct MpiLaunchSettings {
    std::filesystem::path hostfile;  // mpirun --hostfile (empty: mpirun's default hosts)
    int ranks = 0;                   // mpirun -np; 0 = diagnoses run inside the service
    std::filesystem::path triax;     // the triax CLI; the same path on every host
    std::string mpirun = "mpirun";
    bool enabled() const { return ranks > 0; }
};

// What the child is asked to diagnose (written as scheme.json, dataset.json, options.json).
struct MpiDiagnosisInputs {
    nlohmann::json scheme;   // scheme document (scheme.schema.json)
    nlohmann::json dataset;  // lab dataset in the JSON upload form (io::lab_dataset_to_json)
    nlohmann::json options;  // diagnose options (io::diagnose_options_from_json reads them)
};

// The command line the job runs (for the log and the tests).
std::vector<std::string> mpi_diagnosis_command(const MpiLaunchSettings& settings, const std::filesystem::path& dir);

// Runs the diagnosis in `dir` (created) and returns the report JSON (the same
// serialisation as an in-process diagnosis: io::diagnosis_report_to_json). Throws
// diagnose::DiagnosisCancelled when the observer cancels, std::runtime_error naming the exit
// status and the child's last stderr lines when it fails.
nlohmann::json run_diagnosis_over_mpi(const MpiLaunchSettings& settings, const std::filesystem::path& dir,
                                      const MpiDiagnosisInputs& inputs, diagnose::DiagnoseObserver& observer);

}  // namespace triax::scaleout
