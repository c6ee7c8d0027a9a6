// Lab files that are wrong in ways a parser can miss: numbers in other notations, values
// no logger writes, another field separator, and a stage column without a kind column
// (lab exports number every stage, shear included). Each case fails against readers that
// accept the value or guess the kind from the stage number.
#include "server/io/lab_format.hpp"
#include "server/io/lab_table.hpp"
#include "service_fixture.hpp"

using namespace triax;
using namespace triax::test;

namespace {
std::string csv_error(const std::string& text) {
    try {
        io::parse_lab_csv(text);
    } catch (const io::LabParseError& e) {
        return e.what();
    }
    return "accepted";
}
std::string gds_error(const std::string& text) {
    try {
        io::parse_lab_gds(text);
    } catch (const io::LabParseError& e) {
        return e.what();
    }
    return "accepted";
}
const std::string kGdsHead =
    "Stage Number,Time since start of stage (s),Radial Pressure (kPa),Axial Displacement (mm),Axial Strain (%),"
    "Deviator Stress (kPa)\n";
}  // namespace

TEST_CASE("lab numbers are decimal only: 0x10, inf and nan are refused", "[server][lab][hostile]") {
    CHECK_FALSE(io::finite_number("0x10"));
    CHECK_FALSE(io::finite_number("inf"));
    CHECK_FALSE(io::finite_number("nan"));
    CHECK_FALSE(io::finite_number("1e400"));
    CHECK_FALSE(io::finite_number("12 mm"));
    CHECK(io::finite_number("1.5e3") == 1500.0);
    CHECK(io::finite_number(" -2.5 ") == -2.5);
    CHECK(io::finite_number("+3") == 3.0);
    CHECK(csv_error("confining_kPa,axial_strain_pct,q_kPa\n100,0.5,0x10\n").find("line 2, column 9") == 0);
}

TEST_CASE("GDS: stage numbers, clocks and displacements a logger cannot write are refused", "[server][lab][hostile]") {
    const std::string ok = kGdsHead + "1,0,100,0,0,10\n1,60,100,0.1,0.05,20\n";
    CHECK(gds_error(ok) == "accepted");
    CHECK(gds_error(kGdsHead + "-3,0,100,0,0,10\n-3,60,100,0.1,0.05,20\n").find("stage number") != std::string::npos);
    CHECK(gds_error(kGdsHead + "2.5,0,100,0,0,10\n2.5,60,100,0.1,0.05,20\n").find("integer") != std::string::npos);
    CHECK(gds_error(kGdsHead + "1,60,100,0,0,10\n1,30,100,0.1,0.05,20\n").find("backwards") != std::string::npos);
    CHECK(gds_error(kGdsHead + "1,0,100,0,0,10\n1,60,100,1e308,0.05,20\n").find("line 3") == 0);
}

TEST_CASE("AGS: a negative cell pressure is refused as in the CSV reader", "[server][lab][hostile]") {
    const std::string ags = "\"GROUP\",\"TRET\"\n\"HEADING\",\"LOCA_ID\",\"TRET_CELL\",\"TRET_DEVF\"\n"
                            "\"UNIT\",\"\",\"kPa\",\"kPa\"\n\"TYPE\",\"ID\",\"2DP\",\"2DP\"\n"
                            "\"DATA\",\"BH1\",\"-50\",\"120\"\n";
    try {
        io::parse_lab_ags(ags);
        FAIL("a negative cell pressure was accepted");
    } catch (const io::LabParseError& e) {
        CHECK(std::string(e.what()).find("TRET_CELL") != std::string::npos);
        CHECK(e.line == 5);
    }
    CHECK(csv_error("confining_kPa,axial_strain_pct,q_kPa\n-50,0.5,10\n") != "accepted");
}

TEST_CASE("AGS: a group or HEADING given twice is refused (found by fuzzing: heap overflow)", "[server][lab][hostile]") {
    const std::string first = "\"GROUP\",\"TRET\"\n\"HEADING\",\"LOCA_ID\"\n\"DATA\",\"BH1\"\n";
    const std::string again = "\"GROUP\",\"TRET\"\n\"HEADING\",\"LOCA_ID\",\"SAMP_ID\",\"TRET_CELL\"\n";
    CHECK_THROWS_AS(io::parse_lab_ags(first + again), io::LabParseError);
    CHECK_THROWS_AS(io::parse_lab_ags("\"GROUP\",\"TRET\"\n\"HEADING\",\"LOCA_ID\"\n\"DATA\",\"BH1\"\n"
                                      "\"HEADING\",\"LOCA_ID\",\"SAMP_ID\",\"TRET_CELL\"\n"),
                    io::LabParseError);
}

TEST_CASE("semicolon and tab separated CSV are read (decimal comma with semicolons), and said so", "[server][lab][hostile]") {
    std::vector<std::string> notes;
    const auto d = io::parse_lab_csv("confining_kPa;axial_strain_pct;q_kPa\n100;0,5;80\n100;1,0;120\n", &notes);
    REQUIRE(d.curves.size() == 1);
    CHECK(d.curves[0].axial_strain[0] == Approx(0.005));
    CHECK(d.curves[0].deviator_pa[1] == Approx(120e3));
    REQUIRE(notes.size() == 1);
    CHECK(notes[0].find("';'") != std::string::npos);
    const auto t = io::parse_lab_csv("confining_kPa\taxial_strain_pct\tq_kPa\n100\t0.5\t80\n");
    CHECK(t.curves[0].deviator_pa[0] == Approx(80e3));
    // A separator the reader cannot use is named in the error.
    CHECK(csv_error("confining_kPa|axial_strain_pct|q_kPa\n100|0.5|80\n").find("separated") != std::string::npos);
}

TEST_CASE("a stage column without kind: the kind is read from q, said in the answer, refused when ambiguous",
          "[server][lab][hostile]") {
    // A drained shear test exported with its stage number (1): q ramps.
    std::string shear = "stage,confining_kPa,axial_strain_pct,q_kPa\n";
    for (int i = 0; i <= 10; ++i) shear += "1,100," + std::to_string(0.5 * i) + "," + std::to_string(20 * i) + "\n";
    std::vector<std::string> notes;
    auto d = io::parse_lab_csv(shear, &notes);
    REQUIRE(d.curves.size() == 1);
    CHECK(d.curves[0].kind == diagnose::CurveKind::Shear);
    REQUIRE(notes.size() == 1);
    CHECK(notes[0].find("stage 1 at 100 kPa: read as shear") == 0);
    // A creep stage holds q.
    std::string creep = "stage,confining_kPa,time_min,axial_deformation_mm,q_kPa\n";
    for (int i = 0; i <= 10; ++i)
        creep += "2,100," + std::to_string(10 * i) + "," + std::to_string(0.1 + 0.01 * i) + "," + (i % 2 ? "151" : "149") + "\n";
    notes.clear();
    d = io::parse_lab_csv(creep, &notes);
    REQUIRE(d.curves.size() == 1);
    CHECK(d.curves[0].kind == diagnose::CurveKind::Creep);
    CHECK(d.curves[0].stage == 2);
    CHECK(notes.at(0).find("read as creep") != std::string::npos);
    // Neither: refused, asking for a kind column.
    CHECK(csv_error("stage,confining_kPa,q_kPa\n1,100,50\n1,100,52\n1,100,70\n1,100,50\n")
              .find("add a kind column") != std::string::npos);
    CHECK(csv_error("stage,confining_kPa,time_min,axial_deformation_mm\n1,100,0,0.1\n1,100,5,0.2\n")
              .find("add a kind column") != std::string::npos);
    // Through the service: the answer carries the note.
    ScriptControl control;
    TestServer srv(scripted_executor(control));
    const auto up = srv.post("/datasets?format=csv", shear, "text/csv");
    REQUIRE(up.status == 201);
    CHECK(up.body["curves"][0]["kind"] == "shear");
    CHECK(up.body["notes"][0].get<std::string>().find("read as shear") != std::string::npos);
}

TEST_CASE("common column aliases are read: vol_strain_pct, cell_pressure_kPa, deviator_stress_kPa", "[server][lab][hostile]") {
    const auto d = io::parse_lab_csv("cell_pressure_kPa,axial_strain_pct,deviator_stress_kPa,vol_strain_pct\n100,0.5,80,-0.1\n");
    REQUIRE(d.curves.size() == 1);
    CHECK(d.curves[0].volumetric_strain[0] == Approx(-0.001));
    CHECK(d.curves[0].confining_pa == Approx(100e3));
}
