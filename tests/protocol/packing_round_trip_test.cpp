// Packings out and in (docs/packings.md): an exported snapshot read back gives the same
// positions and radii to the last bit in every exact format; the generation snapshot of a
// run, imported as the specimen of the same scheme, gives the same run; the LAMMPS and VTK
// files parse back; bad files are refused naming the line.
#include <catch2/catch.hpp>

#include <cstring>
#include <optional>
#include <sstream>

#include "engine/protocol/imported_packing.hpp"
#include "engine/protocol/specimen.hpp"
#include "engine/protocol/triaxial_test.hpp"
#include "server/io/packing_formats.hpp"

using namespace triax;
using namespace triax::protocol;

namespace {

// A short run: about 60 grains of 2-4 mm in a 40 x 80 mm specimen, sheared to 1 %.
TestScheme small_scheme() {
    TestScheme s;
    s.name = "round-trip";
    s.specimen.diameter_m = 0.04;
    s.specimen.height_m = 0.08;
    s.gradation.r_min_m = 2.0e-3;
    s.gradation.radius_ratio = 2.0;
    s.micro.membrane_particle_radius_m = 4.0e-3;
    s.loading.max_axial_strain = 0.01;
    s.loading.stress_levels = {};
    s.loading.stage_durations_s = {};
    s.max_particles = 60;
    s.seed = 5;
    return s;
}

struct Recorder : RunObserver {
    std::vector<SpecimenSnapshot> snapshots;
    void on_snapshot(const SpecimenSnapshot& s) override { snapshots.push_back(s); }
};

const SpecimenSnapshot& find_stage(const std::vector<SpecimenSnapshot>& v, const std::string& stage) {
    for (const auto& s : v)
        if (s.stage == stage) return s;
    FAIL("no snapshot of stage " << stage);
    return v.front();
}

void require_same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k)
        for (int c = 0; c < 3; ++c) REQUIRE(std::memcmp(&a[k][c], &b[k][c], sizeof(double)) == 0);
}
void require_same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k) REQUIRE(std::memcmp(&a[k], &b[k], sizeof(double)) == 0);
}

// The run of the scheme with its snapshots (cached: one run per process).
const std::pair<TestResult, std::vector<SpecimenSnapshot>>& generated_run() {
    static const auto r = [] {
        Recorder rec;
        auto res = run_triaxial_test(small_scheme(), rec, Phase::Shear);
        return std::make_pair(res, rec.snapshots);
    }();
    return r;
}

// The small scheme starting from a snapshot exported in `format` and read back.
TestScheme scheme_from(const SpecimenSnapshot& snap, io::PackingFormat format) {
    TestScheme s = small_scheme();
    const bool spheres = format == io::PackingFormat::Spheres;
    s.packing = std::make_shared<ImportedPacking>(
        io::parse_packing(io::snapshot_to_text(snap, format), snap.stage + (spheres ? ".txt" : ".json")));
    return s;
}

}  // namespace

TEST_CASE("snapshots are recorded at the end of each stage", "[protocol][packing]") {
    const auto& [res, snaps] = generated_run();
    REQUIRE(snaps.size() == 3);
    CHECK(snaps[0].stage == "generation");
    CHECK(snaps[1].stage == "consolidation");
    CHECK(snaps[2].stage == "shear");
    const auto& shear = snaps[2];
    CHECK(static_cast<int>(shear.count_of(kSoilGroup)) == res.particle_count);
    CHECK(static_cast<int>(shear.count_of(kMembraneGroup)) == res.membrane_particle_count);
    // Displacements are measured from the start of consolidation: none at generation, and
    // the top platen's 1 % (0.8 mm) shows in the grains after the shear.
    for (const auto& d : snaps[0].displacement) CHECK(d.norm() == 0.0);
    double dz_max = 0.0;
    for (std::size_t k = 0; k < shear.particle_count(); ++k)
        if (shear.group[k] == kSoilGroup) dz_max = std::max(dz_max, -shear.displacement[k].z());
    CHECK(dz_max > 0.3e-3);
    REQUIRE(shear.platens.size() == 2);
    CHECK(shear.platens[1].name == "top");
    CHECK(shear.platens[1].normal_force_n > 0.0);
    CHECK(shear.measurement_spheres.size() == 3);
    for (std::size_t k = 0; k < shear.contact_count(); ++k) REQUIRE(shear.contact_i[k] < shear.contact_j[k]);
}

TEST_CASE("export then import gives the same positions and radii to the last bit", "[protocol][packing]") {
    const auto& snap = find_stage(generated_run().second, "consolidation");
    SECTION("stored form") {
        const auto back = io::decode_snapshot(io::encode_snapshot(snap));
        require_same_bits(back.position, snap.position);
        require_same_bits(back.radius, snap.radius);
        require_same_bits(back.normal_force_n, snap.normal_force_n);
        CHECK(back.contact_i == snap.contact_i);
        CHECK(back.group_names == snap.group_names);
    }
    SECTION("project JSON") {
        const auto text = io::snapshot_to_text(snap, io::PackingFormat::Project);
        const auto back = io::snapshot_from_project_json(nlohmann::json::parse(text));
        require_same_bits(back.position, snap.position);
        require_same_bits(back.radius, snap.radius);
        require_same_bits(back.velocity, snap.velocity);
        require_same_bits(back.shear_force_n, snap.shear_force_n);
        CHECK(back.bonded == snap.bonded);
        const auto p = io::parse_packing(text, "export.json");
        CHECK(p.size() == snap.count_of(kSoilGroup));
        for (std::size_t k = 0; k < p.size(); ++k) REQUIRE(std::memcmp(&p.radius[k], &snap.radius[k], sizeof(double)) == 0);
    }
    SECTION("sphere list") {
        const auto p = io::parse_packing(io::snapshot_sphere_list(snap), "export.txt");
        REQUIRE(p.size() == snap.count_of(kSoilGroup));  // grains come first; membrane rows skipped
        std::vector<Vec3> x(snap.position.begin(), snap.position.begin() + p.size());
        std::vector<double> r(snap.radius.begin(), snap.radius.begin() + p.size());
        require_same_bits(p.position, x);
        require_same_bits(p.radius, r);
        CHECK(p.line.front() == 4);  // three header lines
    }
}

TEST_CASE("an imported packing is the same specimen as the generated one it came from", "[protocol][packing]") {
    const TestScheme s = small_scheme();
    const Specimen generated(s);
    const auto snap = snapshot_of(generated, s, "generation");
    TestScheme t = s;
    t.packing = std::make_shared<ImportedPacking>(io::parse_packing(io::snapshot_to_text(snap, io::PackingFormat::Project), "g.json"));
    const Specimen imported(t);
    const auto& a = generated.world().particles();
    const auto& b = imported.world().particles();
    REQUIRE(a.size() == b.size());
    require_same_bits(b.position, a.position);
    require_same_bits(b.radius, a.radius);
    require_same_bits(b.mass, a.mass);
    require_same_bits(b.inertia, a.inertia);
    require_same_bits(b.velocity, a.velocity);
    require_same_bits(b.angular_velocity, a.angular_velocity);
    CHECK(b.group == a.group);
    CHECK(b.flags == a.flags);
    CHECK(imported.world().time_step() == generated.world().time_step());
    CHECK(imported.soil_kn() == generated.soil_kn());
    CHECK(imported.mean_diameter() == generated.mean_diameter());
}

TEST_CASE("an imported packing gives the same run as the generated one it came from", "[protocol][packing]") {
    const auto& [res, snaps] = generated_run();
    const TestScheme s = scheme_from(find_stage(snaps, "generation"), io::PackingFormat::Project);
    Recorder rec;
    const auto again = run_triaxial_test(s, rec, Phase::Shear);
    CHECK(again.particle_count == res.particle_count);
    CHECK(again.consolidation.steps == res.consolidation.steps);
    REQUIRE(again.shear.size() == res.shear.size());
    for (std::size_t k = 0; k < res.shear.size(); ++k) {
        CHECK(again.shear[k].axial_strain == res.shear[k].axial_strain);
        CHECK(again.shear[k].q_pa == res.shear[k].q_pa);
        CHECK(again.shear[k].volumetric_strain == res.shear[k].volumetric_strain);
    }
    require_same_bits(find_stage(rec.snapshots, "shear").position, find_stage(snaps, "shear").position);
}

// Every stage a run exports (generation, consolidation, shear, each creep-k the scheme
// has) comes back as the specimen of the same scheme: the grains and the membrane's
// spheres exactly where they were, the platens where the export recorded them (project
// JSON) or touching the outermost grains (a sphere list names no platens), so a
// consolidated specimen that has shrunk and has grains pressed into its platens keeps its
// height, its wrinkled membrane and its platen contacts.
TEST_CASE("every stage a run exports imports as the specimen of the same scheme", "[protocol][packing]") {
    const auto& snaps = generated_run().second;
    REQUIRE(snaps.size() >= 3);
    for (const auto& snap : snaps) {
        for (const auto format : {io::PackingFormat::Spheres, io::PackingFormat::Project}) {
            const bool spheres = format == io::PackingFormat::Spheres;
            INFO("stage " << snap.stage << (spheres ? ", sphere list" : ", project JSON"));
            const TestScheme t = scheme_from(snap, format);
            REQUIRE_NOTHROW(validate_packing(*t.packing, t));
            const Specimen imported(t);
            const std::size_t n = snap.count_of(kSoilGroup);
            REQUIRE(imported.soil_count() == static_cast<int>(n));
            const auto& p = imported.world().particles();
            require_same_bits(std::vector<Vec3>(p.position.begin(), p.position.begin() + n),
                              std::vector<Vec3>(snap.position.begin(), snap.position.begin() + n));
            double lo = 1e9, hi = -1e9;
            for (std::size_t q = 0; q < n; ++q) {
                lo = std::min(lo, snap.position[q].z() - snap.radius[q]);
                hi = std::max(hi, snap.position[q].z() + snap.radius[q]);
            }
            // The membrane as it was (wrinkled by the consolidation, bulged by the shear).
            REQUIRE(imported.membrane_particle_count() == static_cast<int>(snap.count_of(kMembraneGroup)));
            require_same_bits(std::vector<Vec3>(p.position.begin() + n, p.position.end()),
                              std::vector<Vec3>(snap.position.begin() + n, snap.position.end()));
            REQUIRE(snap.platens.size() == 2);
            if (spheres) {
                CHECK(imported.bottom_z() == lo);
                CHECK(imported.top_z() == hi);
            } else {
                CHECK(imported.bottom_z() == snap.platens[0].point.z());
                CHECK(imported.top_z() == snap.platens[1].point.z());
            }
        }
    }
}

// The case of the report: the consolidated state as a sphere list, run again on the same
// scheme, consolidates (and with it shears: the shear starts from this state).
TEST_CASE("a consolidated packing exported as a sphere list runs on the same scheme", "[protocol][packing]") {
    const auto& consolidated = find_stage(generated_run().second, "consolidation");
    const TestScheme t = scheme_from(consolidated, io::PackingFormat::Spheres);
    RunObserver none;
    const auto again = run_triaxial_test(t, none, Phase::Consolidation);
    CHECK(again.particle_count == static_cast<int>(consolidated.count_of(kSoilGroup)));
    CHECK(again.membrane_particle_count == static_cast<int>(consolidated.count_of(kMembraneGroup)));
    CHECK(again.consolidation.steps > 0);
    CHECK(again.consolidation.achieved_sigma3_pa == Approx(t.loading.confining_pressure_pa).epsilon(0.05));
}

TEST_CASE("LAMMPS and VTK exports parse back", "[protocol][packing]") {
    const auto& snap = find_stage(generated_run().second, "shear");
    const std::size_t n = snap.particle_count(), m = snap.contact_count();
    SECTION("LAMMPS data, atom_style sphere") {
        std::istringstream in(io::snapshot_lammps_data(snap));
        std::string line;
        std::getline(in, line);
        CHECK(line.find("LAMMPS") == 0);
        std::size_t atoms = 0;
        int types = 0;
        while (std::getline(in, line) && line.find("Atoms") == std::string::npos) {
            std::istringstream ls(line);
            std::size_t v;
            std::string w1, w2;
            if (ls >> v >> w1) {
                if (w1 == "atoms") atoms = v;
                if (w1 == "atom" && (ls >> w2) && w2 == "types") types = static_cast<int>(v);
            }
        }
        CHECK(line == "Atoms # sphere");
        CHECK(atoms == n);
        CHECK(types == 2);
        std::getline(in, line);  // blank
        for (std::size_t k = 0; k < n; ++k) {
            REQUIRE(std::getline(in, line));
            std::istringstream ls(line);
            long id;
            int type;
            double d, rho, x, y, z;
            REQUIRE(static_cast<bool>(ls >> id >> type >> d >> rho >> x >> y >> z));
            CHECK(id == static_cast<long>(k + 1));
            CHECK(type == snap.group[k] + 1);
            REQUIRE(d == 2.0 * snap.radius[k]);
            REQUIRE(x == snap.position[k].x());
            REQUIRE(z == snap.position[k].z());
            CHECK(rho > 0.0);
        }
    }
    SECTION("legacy VTK POLYDATA") {
        std::istringstream in(io::snapshot_vtk(snap));
        std::string line, word;
        std::getline(in, line);
        CHECK(line == "# vtk DataFile Version 3.0");
        std::getline(in, line);
        std::getline(in, line);
        CHECK(line == "ASCII");
        std::getline(in, line);
        CHECK(line == "DATASET POLYDATA");
        std::size_t count;
        in >> word >> count >> line;
        CHECK(word == "POINTS");
        REQUIRE(count == n);
        for (std::size_t k = 0; k < n; ++k) {
            double x, y, z;
            REQUIRE(static_cast<bool>(in >> x >> y >> z));
            REQUIRE(y == snap.position[k].y());
        }
        std::size_t lines, ints;
        in >> word >> lines >> ints;
        CHECK(word == "LINES");
        REQUIRE(lines == m);
        CHECK(ints == 3 * m);
        for (std::size_t k = 0; k < m; ++k) {
            int two, i, j;
            REQUIRE(static_cast<bool>(in >> two >> i >> j));
            REQUIRE(two == 2);
            REQUIRE(i == snap.contact_i[k]);
            REQUIRE(j == snap.contact_j[k]);
        }
        in >> word >> count;
        CHECK(word == "POINT_DATA");
        CHECK(count == n);
        std::string type;
        in >> word >> line >> type;
        CHECK(word == "SCALARS");
        CHECK(line == "radius_m");
        std::getline(in, line);
        std::getline(in, line);
        CHECK(line == "LOOKUP_TABLE default");
        for (std::size_t k = 0; k < n; ++k) {
            double r;
            REQUIRE(static_cast<bool>(in >> r));
            REQUIRE(r == snap.radius[k]);
        }
        const std::string rest((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        CHECK(rest.find("CELL_DATA " + std::to_string(m)) != std::string::npos);
        CHECK(rest.find("SCALARS normal_force_N double 1") != std::string::npos);
    }
}

TEST_CASE("bad packings are refused naming the line and the cause", "[protocol][packing]") {
    auto message = [](const std::string& text, std::optional<std::string> units = std::nullopt) {
        try {
            io::parse_packing(text, "f.txt", units);
        } catch (const io::PackingParseError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    CHECK(message("# a packing\n0 0 0 0.001\n").find("f.txt line 2: no unit stated") == 0);
    CHECK(message("# units: inch\n0 0 0 1\n").find("line 1: unknown unit 'inch'") != std::string::npos);
    CHECK(message("# units: m\n0 0 0\n").find("line 2: expected 4 or 5 columns") != std::string::npos);
    CHECK(message("# x_mm y_mm z_mm r_mm\n0 0 0 -1\n").find("line 2: radius must be positive") != std::string::npos);
    CHECK(message("# units: mm\n0 0 0 1 7\n").find("line 2: group must be") != std::string::npos);
    CHECK(message("0 0 nan 1\n", "mm").find("line 1: column z") != std::string::npos);
    CHECK(message("# units: m\n# units: mm\n0 0 0 1\n").find("contradicts") != std::string::npos);
    CHECK(message("{\"format\": \"triax-packing\", \"particles\": {}}").find("units") != std::string::npos);
    CHECK(message("{\"format\": \"triax-packing\", \"units\": \"SI\", \"particles\": {\"x_m\": [0], \"y_m\": [0]}}")
              .find("missing field 'z_m'") != std::string::npos);

    const TestScheme s = small_scheme();  // 40 x 80 mm
    auto invalid = [&](const std::string& text) {
        try {
            const bool has_unit = text.find("# units") != std::string::npos;
            validate_packing(io::parse_packing(text, "f.txt", has_unit ? std::nullopt : std::optional<std::string>("mm")), s);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("valid");
    };
    // A column of grains spanning the specimen, with a grain out to the membrane.
    const std::string column = "0 0 -37 3\n0 0 37 3\n17 0 0 3\n";
    CHECK(invalid(column + "0 0 0 3\n0 0 6.5 3\n") == "valid");
    CHECK(invalid(column + "0 0 0 3\n0 0 4 3\n").find("f.txt line 5: grain overlaps the grain of f.txt line 4 by 66.7 %") == 0);
    // The packing's own extent is the specimen: grains pressed into the platens (here by
    // 1.5 mm, half a radius), or a specimen that has shrunk or bulged, are taken as they are.
    CHECK(invalid("0 0 -38.5 3\n0 0 38.5 3\n17 0 0 3\n") == "valid");
    CHECK(invalid("0 0 -30 3\n0 0 30 3\n15 0 0 3\n") == "valid");
    CHECK(invalid("0 0 -37 3\n0 0 37 3\n23 0 0 3\n") == "valid");
    // Far outside: beyond the specimen by more than half its radius or half-height.
    CHECK(invalid(column + "28 0 0 3\n").find("f.txt line 4: grain outside the specimen: it reaches radius 31 mm") == 0);
    CHECK(invalid(column + "0 0 58 3\n").find("f.txt line 4: grain outside the specimen: z from") == 0);
    // Origin at the base instead of the centre: the top grains pass the top by H/2.
    CHECK(invalid("0 0 3 3\n0 0 77 3\n17 0 40 3\n").find("f.txt line 2: grain outside the specimen: z from") == 0);
    // Millimetres read as metres: a 3 m grain crosses the platens; metres read as
    // millimetres: a specimen a thousand times too small.
    CHECK(invalid("# units: m\n0 0 0 3\n").find("outside the specimen") != std::string::npos);
    CHECK(invalid("0 0 -0.037 0.003\n0 0 0.037 0.003\n0.017 0 0 0.003\n").find("f.txt: the grains span") == 0);
    CHECK(invalid("0 0 -37 3\n0 0 37 3\n").find("f.txt: the grains span a diameter of 6 mm") == 0);
}
