// `triax run scheme.json --out DIR` / `triax run --group B --out DIR`: runs the whole
// protocol headless, prints a progress line (stage, %, ETA) on stderr and writes
// summary.json, result.json, one CSV per series and the specimen at the end of each stage
// (snapshots/<stage>.snap, the stored form of server/io/packing_codec.cpp) into DIR.
// `--packing FILE` starts from an imported packing (docs/packings.md).
// `triax export DIR --stage S --format F [--out FILE]` writes a stored snapshot of DIR in
// format F (json, project, spheres, lammps, vtk).
// `triax diagnose` and `triax ensemble` (scaleout_commands.cpp) run on threads or, under
// mpirun, on MPI ranks.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>

#include "engine/core/types.hpp"
#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/bounded_json.hpp"
#include "engine/protocol/imported_packing.hpp"
#include "server/io/packing_formats.hpp"
#include "server/cli/commands.hpp"
#include "server/io/result_csv.hpp"
#include "server/io/result_json.hpp"
#include "server/io/scheme_json.hpp"
#include "server/io/scheme_schema.hpp"

namespace {

const char* kUsage =
    "usage: triax run <scheme.json> [--out DIR] [--threads N] [--packing FILE [--units m|mm]]\n"
    "       triax run --group A|B|C|D|E [--out DIR] [--threads N] [--max-particles N]\n"
    "       triax export <RUN_DIR> --stage generation|consolidation|shear|creep-K\n"
    "                    --format json|project|spheres|lammps|vtk [--out FILE]\n"
    "       triax presets            (prints the paper groups as JSON)\n"
    "       triax scheme-schema      (prints schema/scheme.schema.json, written from the scheme's field table)\n"
    "       triax diagnose --scheme SCHEME.json --dataset LAB_FILE [--format csv|gds|ags|json]\n"
    "                      [--options OPTIONS.json] [--out REPORT.json]\n"
    "       triax ensemble --scheme SCHEME.json --seeds 1-8 [--out DIR] [--concurrency N]\n"
    "                      [--threads N] [--max-particles N]\n"
    "       (diagnose and ensemble spread their runs over the ranks of `mpirun -np N triax ...`)\n";

class StderrProgress : public triax::protocol::RunObserver {
public:
    explicit StderrProgress(std::filesystem::path snapshot_dir) : snapshot_dir_(std::move(snapshot_dir)) {}
    void on_snapshot(const triax::protocol::SpecimenSnapshot& s) override {
        std::filesystem::create_directories(snapshot_dir_);
        const auto path = snapshot_dir_ / (s.stage + ".snap");
        std::ofstream f(path, std::ios::binary);
        if (!f || !(f << triax::io::encode_snapshot(s))) throw std::runtime_error("cannot write " + path.string());
    }
    void progress(const std::string& stage, double fraction, double eta_s) override {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::milliseconds(500) && fraction < 1.0) return;
        last_ = now;
        std::fprintf(stderr, "\r%-14s %5.1f %%  ETA %s   ", stage.c_str(), 100.0 * fraction,
                     eta_s < 0 ? "--" : (std::to_string(static_cast<long>(eta_s)) + " s").c_str());
        std::fflush(stderr);
    }
    void stage_changed(const std::string& stage, int, double s, double q) override {
        if (stage.rfind("creep", 0) == 0)
            std::fprintf(stderr, "\n%s: S = %.2f, q = %.1f kPa\n", stage.c_str(), s, q * 1e-3);
        else
            std::fprintf(stderr, "\n%s\n", stage.c_str());
    }

private:
    std::filesystem::path snapshot_dir_;
    std::chrono::steady_clock::time_point last_{};
};

void write_file(const std::filesystem::path& p, const std::string& text) {
    std::ofstream f(p);
    if (!f) throw std::runtime_error("cannot write " + p.string());
    f << text;
}

int run(int argc, char** argv) {
    std::string scheme_path, group, out = "triax-out", packing_path;
    std::optional<std::string> units;
    int threads = 0, max_particles = -1;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&](const char* what) -> std::string {
            if (i + 1 >= argc) throw std::invalid_argument(std::string(what) + " needs a value");
            return argv[++i];
        };
        if (a == "--out") out = next("--out");
        else if (a == "--group") group = next("--group");
        else if (a == "--threads") threads = std::stoi(next("--threads"));
        else if (a == "--max-particles") max_particles = std::stoi(next("--max-particles"));
        else if (a == "--packing") packing_path = next("--packing");
        else if (a == "--units") units = next("--units");
        else if (!a.empty() && a[0] == '-') throw std::invalid_argument("unknown option " + a);
        else scheme_path = a;
    }
    triax::protocol::TestScheme scheme;
    if (!group.empty()) {
        scheme = triax::protocol::paper_group(group);
    } else if (!scheme_path.empty()) {
        std::ifstream f(scheme_path);
        if (!f) throw std::invalid_argument("cannot open " + scheme_path);
        const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        nlohmann::json j;
        try {
            j = triax::io::parse_bounded_json(text);
        } catch (const triax::io::JsonLimitError& e) {
            throw std::invalid_argument(scheme_path + ": " + (e.pointer.empty() ? "" : "field " + e.pointer + ": ") + e.what());
        }
        try {
            scheme = triax::io::scheme_from_json(j);
        } catch (const triax::io::SchemeError& e) {
            throw std::invalid_argument(scheme_path + ": field " + e.field + ": " + e.what());
        }
        scheme = triax::cli::read_scheme_file(scheme_path);
    } else {
        throw std::invalid_argument("give a scheme file or --group");
    }
    if (threads > 0) scheme.threads = threads;
    if (max_particles >= 0) scheme.max_particles = max_particles;
    if (!packing_path.empty()) {
        std::ifstream f(packing_path, std::ios::binary);
        if (!f) throw std::invalid_argument("cannot open " + packing_path);
        std::stringstream text;
        text << f.rdbuf();
        try {
            scheme.packing = std::make_shared<triax::protocol::ImportedPacking>(
                triax::io::parse_packing(text.str(), packing_path, units));
            triax::protocol::validate_packing(*scheme.packing, scheme);
        } catch (const triax::io::PackingParseError& e) {
            throw std::invalid_argument(e.what());
        }
    }
    std::filesystem::create_directories(out);
    write_file(std::filesystem::path(out) / "scheme.json", triax::io::scheme_to_json(scheme).dump(2));
    std::filesystem::remove_all(std::filesystem::path(out) / "snapshots");
    StderrProgress obs(std::filesystem::path(out) / "snapshots");
    const auto result = triax::protocol::run_triaxial_test(scheme, obs);
    std::fprintf(stderr, "\n");
    const auto summary = triax::io::result_summary_to_json(result);
    write_file(std::filesystem::path(out) / "summary.json", summary.dump(2));
    write_file(std::filesystem::path(out) / "result.json", triax::io::result_to_json(result).dump());
    for (const char* s : {"stress_strain", "volumetric", "creep", "creep_raw", "energies", "measurements"})
        write_file(std::filesystem::path(out) / (std::string(s) + ".csv"), triax::io::result_series_to_csv(result, s));
    std::cout << summary.dump(2) << "\n";
    return result.cancelled ? 3 : 0;
}

int export_snapshot(int argc, char** argv) {
    std::string dir, stage, format_name, out;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&](const char* what) -> std::string {
            if (i + 1 >= argc) throw std::invalid_argument(std::string(what) + " needs a value");
            return argv[++i];
        };
        if (a == "--stage") stage = next("--stage");
        else if (a == "--format") format_name = next("--format");
        else if (a == "--out") out = next("--out");
        else if (!a.empty() && a[0] == '-') throw std::invalid_argument("unknown option " + a);
        else dir = a;
    }
    if (dir.empty() || stage.empty() || format_name.empty()) throw std::invalid_argument("export needs RUN_DIR, --stage and --format");
    const auto format = triax::io::packing_format_from_name(format_name);
    if (!format) throw std::invalid_argument("--format must be json, project, spheres, lammps or vtk; got '" + format_name + "'");
    const auto path = std::filesystem::path(dir) / "snapshots" / (stage + ".snap");
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        std::string have;
        if (std::filesystem::is_directory(path.parent_path()))
            for (const auto& e : std::filesystem::directory_iterator(path.parent_path()))
                if (e.path().extension() == ".snap") have += (have.empty() ? "" : ", ") + e.path().stem().string();
        throw std::invalid_argument("no snapshot of stage '" + stage + "' in " + dir + " (recorded: " +
                                    (have.empty() ? std::string("none") : have) + ")");
    }
    std::stringstream bytes;
    bytes << f.rdbuf();
    const auto text = triax::io::snapshot_to_text(triax::io::decode_snapshot(bytes.str()), *format);
    if (out.empty()) std::cout << text;
    else write_file(out, text);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) { std::cerr << kUsage; return 2; }
    const std::string cmd = argv[1];
    try {
        if (cmd == "run") return run(argc, argv);
        if (cmd == "export") return export_snapshot(argc, argv);
        if (cmd == "diagnose") return triax::cli::diagnose_command(argc, argv);
        if (cmd == "ensemble") return triax::cli::ensemble_command(argc, argv);
        if (cmd == "presets") { std::cout << triax::io::presets_to_json().dump(2) << "\n"; return 0; }
        if (cmd == "scheme-schema") { std::cout << triax::io::scheme_schema_text(); return 0; }
        std::cerr << "unknown command '" << cmd << "'\n" << kUsage;
        return 2;
    } catch (const triax::SimulationError& e) {
        std::cerr << "\nsimulation failed: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "\nerror: " << e.what() << "\n";
        return 2;
    }
}
