// `triax run scheme.json --out DIR` / `triax run --group B --out DIR`: runs the whole
// protocol headless, prints a progress line (stage, %, ETA) on stderr and writes
// summary.json, result.json and one CSV per series into DIR.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "engine/core/types.hpp"
#include "engine/protocol/paper_groups.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/result_csv.hpp"
#include "server/io/result_json.hpp"
#include "server/io/scheme_json.hpp"

namespace {

const char* kUsage =
    "usage: triax run <scheme.json> [--out DIR] [--threads N]\n"
    "       triax run --group A|B|C|D|E [--out DIR] [--threads N] [--max-particles N]\n"
    "       triax presets            (prints the paper groups as JSON)\n";

class StderrProgress : public triax::protocol::RunObserver {
public:
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
    std::chrono::steady_clock::time_point last_{};
};

void write_file(const std::filesystem::path& p, const std::string& text) {
    std::ofstream f(p);
    if (!f) throw std::runtime_error("cannot write " + p.string());
    f << text;
}

int run(int argc, char** argv) {
    std::string scheme_path, group, out = "triax-out";
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
        else if (!a.empty() && a[0] == '-') throw std::invalid_argument("unknown option " + a);
        else scheme_path = a;
    }
    triax::protocol::TestScheme scheme;
    if (!group.empty()) {
        scheme = triax::protocol::paper_group(group);
    } else if (!scheme_path.empty()) {
        std::ifstream f(scheme_path);
        if (!f) throw std::invalid_argument("cannot open " + scheme_path);
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(f);
        } catch (const nlohmann::json::parse_error& e) {
            throw std::invalid_argument(scheme_path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
        }
        try {
            scheme = triax::io::scheme_from_json(j);
        } catch (const triax::io::SchemeError& e) {
            throw std::invalid_argument(scheme_path + ": field " + e.field + ": " + e.what());
        }
    } else {
        throw std::invalid_argument("give a scheme file or --group");
    }
    if (threads > 0) scheme.threads = threads;
    if (max_particles >= 0) scheme.max_particles = max_particles;
    std::filesystem::create_directories(out);
    write_file(std::filesystem::path(out) / "scheme.json", triax::io::scheme_to_json(scheme).dump(2));
    StderrProgress obs;
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

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) { std::cerr << kUsage; return 2; }
    const std::string cmd = argv[1];
    try {
        if (cmd == "run") return run(argc, argv);
        if (cmd == "presets") { std::cout << triax::io::presets_to_json().dump(2) << "\n"; return 0; }
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
