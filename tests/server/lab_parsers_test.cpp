// Lab dataset parsers: plain CSV with units, GDS-Lab export, AGS4 TREG/TRET, JSON. Units
// must arrive in SI, and every broken file must be reported with its line and column.
#include "server/io/lab_format.hpp"

#include <catch2/catch.hpp>

using namespace triax;

TEST_CASE("plain CSV with units header groups readings into curves, in SI", "[server][lab]") {
    const auto d = io::parse_lab_csv(
        "kind,stage,confining_kPa,time_min,axial_strain_pct,axial_deformation_mm,q_kPa,volumetric_strain_pct\n"
        "shear,0,100,,0.0,,0,0\n"
        "shear,0,100,,1.0,,150,0.2\n"
        "shear,0,100,,2.0,,210,0.1\n"
        "creep,1,100,0,,0.10,30,\n"
        "creep,1,100,30,,0.15,30,\n"
        "creep,2,100,0,,0.30,120,\n"
        "creep,2,100,60,,0.42,120,\n");
    REQUIRE(d.curves.size() == 3);
    const auto& shear = d.curves[0];
    CHECK(shear.kind == diagnose::CurveKind::Shear);
    CHECK(shear.confining_pa == Approx(100e3));
    CHECK(shear.axial_strain == std::vector<double>{0.0, 0.01, 0.02});
    CHECK(shear.deviator_pa[2] == Approx(210e3));
    CHECK(shear.volumetric_strain[1] == Approx(0.002));
    CHECK(shear.time_s.empty());
    const auto& c2 = d.curves[2];
    CHECK(c2.kind == diagnose::CurveKind::Creep);
    CHECK(c2.stage == 2);
    CHECK(c2.time_s[1] == Approx(3600.0));
    CHECK(c2.axial_deformation_m[1] == Approx(0.42e-3));
}

TEST_CASE("CSV errors name line and column", "[server][lab]") {
    auto error_at = [](const std::string& text) {
        try {
            io::parse_lab_csv(text);
        } catch (const io::LabParseError& e) {
            return std::make_pair(e.line, e.column);
        }
        return std::make_pair(0, 0);
    };
    CHECK(error_at("confining_kPa,q_kPa,strain\n100,1,2\n") == std::make_pair(1, 21));   // unknown column
    CHECK(error_at("confining_kPa,q_kPa,axial_strain_pct\n100,1,2\n100,abc,3\n") == std::make_pair(3, 5));
    CHECK(error_at("confining_kPa,q_kPa,axial_strain_pct\n100,1,2\n100,2\n").first == 3);
    CHECK(error_at("confining_kPa,q_kPa,axial_strain_pct\n100,1,2\n100,,3\n") == std::make_pair(3, 5));  // gap
    CHECK(error_at("q_kPa,axial_strain_pct\n1,2\n").first == 1);  // no confining column
    CHECK(error_at("kind,stage,confining_kPa,q_kPa\ncreep,0,100,5\n").first == 2);  // creep needs a stage
}

TEST_CASE("GDS-Lab export: stages classified, creep deformation from the end of the previous stage", "[server][lab]") {
    const std::string gds =
        "Test Name:,demo\n"
        "Initial Height (mm):,200\n"
        "Initial Diameter (mm):,100\n"
        "Stage Number,Time since start of test (s),Time since start of stage (s),Radial Pressure (kPa),"
        "Back Pressure (kPa),Axial Displacement (mm),Deviator Stress (kPa),Volume Change (mm3)\n"
        "1,0,0,300,200,0.00,0.2,0\n"          // consolidation: q ~ 0 -> skipped
        "1,60,60,300,200,0.05,0.3,100\n"
        "2,120,0,300,200,0.05,0,100\n"        // shear
        "2,180,60,300,200,1.05,80,1670.8\n"
        "2,240,120,300,200,2.05,120,2456.2\n"
        "3,300,0,300,200,2.35,60,2456.2\n"    // creep at 60 kPa
        "3,900,600,300,200,2.45,60.5,2456.2\n"
        "3,1500,1200,300,200,2.50,59.8,2456.2\n";
    const auto d = io::parse_lab_gds(gds);
    REQUIRE(d.curves.size() == 2);
    const auto& shear = d.curves[0];
    CHECK(shear.kind == diagnose::CurveKind::Shear);
    CHECK(shear.confining_pa == Approx(100e3));
    CHECK(shear.axial_strain[0] == Approx(0.0));
    CHECK(shear.axial_strain[2] == Approx(2.0 / 200.0));
    const double v0 = 3.14159265358979 * 0.25 * 100 * 100 * 200;
    CHECK(shear.volumetric_strain[2] == Approx((2456.2 - 100) / v0));
    const auto& creep = d.curves[1];
    CHECK(creep.kind == diagnose::CurveKind::Creep);
    CHECK(creep.stage == 1);
    CHECK(creep.axial_deformation_m[0] == Approx((2.35 - 2.05) * 1e-3));
    CHECK(creep.axial_deformation_m[2] == Approx((2.50 - 2.05) * 1e-3));
    CHECK(creep.time_s[2] == Approx(1200.0));
}

TEST_CASE("GDS-Lab export without the stage clock rebases the test clock per stage", "[server][lab]") {
    const auto d = io::parse_lab_gds(
        "Stage Number,Time since start of test (s),Radial Pressure (kPa),Axial Strain (%),Deviator Stress (kPa)\n"
        "4,1000,100,1.0,50\n4,1600,100,1.1,50.5\n4,2200,100,1.15,49.9\n");
    REQUIRE(d.curves.size() == 1);
    CHECK(d.curves[0].kind == diagnose::CurveKind::Creep);
    CHECK(d.curves[0].time_s == std::vector<double>{0.0, 600.0, 1200.0});
    CHECK(d.curves[0].axial_strain[2] == Approx(0.0015));  // from the first reading (no earlier stage)
}

TEST_CASE("GDS-Lab export errors", "[server][lab]") {
    CHECK_THROWS_AS(io::parse_lab_gds("a,b\n1,2\n"), io::LabParseError);
    try {
        io::parse_lab_gds("Stage Number,Time since start of stage (s),Radial Pressure (kPa),Axial Strain (%),Deviator Stress (kPa)\n"
                          "1,0,100,0,0\n1,x,100,1,50\n");
        FAIL("no error");
    } catch (const io::LabParseError& e) {
        CHECK(e.line == 3);
        CHECK(e.column == 3);
    }
    // The preamble's specimen size is a whole finite number ("nan" and "80 mm" used to pass).
    for (const char* height : {"nan", "80 mm", "inf"}) {
        INFO(height);
        try {
            io::parse_lab_gds(std::string("Initial Height (mm),") + height +
                              "\nStage Number,Time since start of stage (s),Radial Pressure (kPa),Axial Displacement (mm),"
                              "Deviator Stress (kPa)\n1,0,100,0,0\n1,1,100,1,50\n");
            FAIL("no error");
        } catch (const io::LabParseError& e) {
            CHECK(e.line == 1);
            CHECK(e.column > 1);
            CHECK(std::string(e.what()).find("Initial Height") != std::string::npos);
        }
    }
}

TEST_CASE("AGS4 TRET/TREG summary rows with units", "[server][lab]") {
    const std::string ags =
        "\"GROUP\",\"TREG\"\n"
        "\"HEADING\",\"LOCA_ID\",\"SAMP_ID\",\"TREG_TYPE\",\"TREG_COH\",\"TREG_PHI\"\n"
        "\"UNIT\",\"\",\"\",\"\",\"kPa\",\"deg\"\n"
        "\"TYPE\",\"ID\",\"ID\",\"PA\",\"2DP\",\"1DP\"\n"
        "\"DATA\",\"BH1\",\"S1\",\"CIDC\",\"25\",\"32.0\"\n"
        "\n"
        "\"GROUP\",\"TRET\"\n"
        "\"HEADING\",\"LOCA_ID\",\"SAMP_ID\",\"TRET_TESN\",\"TRET_CELL\",\"TRET_DEVF\",\"TRET_STRN\",\"TRET_IMC\",\"TRET_DDEN\"\n"
        "\"UNIT\",\"\",\"\",\"\",\"kPa\",\"kPa\",\"%\",\"%\",\"Mg/m3\"\n"
        "\"TYPE\",\"ID\",\"ID\",\"X\",\"0DP\",\"0DP\",\"1DP\",\"1DP\",\"2DP\"\n"
        "\"DATA\",\"BH1\",\"S1\",\"1\",\"50\",\"180\",\"4.5\",\"8.9\",\"2.06\"\n"
        "\"DATA\",\"BH1\",\"S1\",\"2\",\"100\",\"290\",\"5.0\",\"8.9\",\"2.05\"\n";
    const auto d = io::parse_lab_ags(ags);
    REQUIRE(d.summary.size() == 2);
    CHECK(d.curves.empty());
    CHECK(d.summary[1].confining_pa == Approx(100e3));
    CHECK(d.summary[1].deviator_at_failure_pa == Approx(290e3));
    CHECK(d.summary[1].strain_at_failure == Approx(0.05));
    CHECK(d.summary[0].dry_density_kg_m3 == Approx(2060.0));
    CHECK(d.summary[0].cohesion_pa == Approx(25e3));
    CHECK(d.summary[0].friction_angle_deg == Approx(32.0));
    CHECK(d.summary[0].specimen == "BH1/S1/1");
    try {
        io::parse_lab_ags("\"GROUP\",\"TRET\"\n\"HEADING\",\"TRET_CELL\"\n\"UNIT\",\"kPa\"\n\"DATA\",\"fifty\"\n");
        FAIL("no error");
    } catch (const io::LabParseError& e) {
        CHECK(e.line == 4);
        CHECK(e.column == 8);
    }
}

TEST_CASE("JSON upload round-trips through the stored form - errors name the pointer", "[server][lab]") {
    const auto doc = nlohmann::json::parse(R"({"name":"lab","curves":[
        {"kind":"creep","stage":2,"confining_kPa":100,"columns":["time_min","axial_deformation_mm"],"rows":[[0,0.1],[30,0.2]]},
        {"kind":"shear","confining_kPa":100,"columns":["axial_strain_pct","q_kPa"],"rows":[[0,0],[1,100]]}]})");
    const auto d = io::parse_lab_json(doc);
    REQUIRE(d.curves.size() == 2);
    CHECK(d.curves[0].time_s[1] == Approx(1800.0));
    CHECK(d.curves[1].deviator_pa[1] == Approx(100e3));
    const auto again = io::parse_lab_json(io::lab_dataset_to_json(d));
    CHECK(again.curves[0].axial_deformation_m == d.curves[0].axial_deformation_m);
    CHECK(again.curves[1].axial_strain == d.curves[1].axial_strain);
    try {
        io::parse_lab_json(nlohmann::json::parse(
            R"({"curves":[{"kind":"shear","confining_kPa":100,"columns":["axial_strain_pct","q_kPa"],"rows":[[0,"x"]]}]})"));
        FAIL("no error");
    } catch (const io::LabParseError& e) {
        CHECK(e.field == "/curves/0/rows/0/1");
    }
}

TEST_CASE("format sniffing", "[server][lab]") {
    CHECK(io::sniff_lab_format(" {\"curves\":[]}") == io::LabFormat::Json);
    CHECK(io::sniff_lab_format("\"GROUP\",\"TRET\"\n") == io::LabFormat::Ags);
    CHECK(io::sniff_lab_format("Stage Number,Time since start of stage (s)\n") == io::LabFormat::Gds);
    CHECK(io::sniff_lab_format("confining_kPa,q_kPa\n") == io::LabFormat::Csv);
}
