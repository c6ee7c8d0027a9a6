// A diagnosis's membrane stiffness K_m delivered as the scheme's membrane modulus
// (server/diagnoses/membrane_modulus.hpp): E_m = K_m D / (4 t_m), the engine's relation.
#include "server/diagnoses/membrane_modulus.hpp"

#include "engine/protocol/membrane_compliance.hpp"

#include <catch2/catch.hpp>

using nlohmann::json;
using namespace triax;

TEST_CASE("membrane_stiffness parameters carry the scheme's membrane modulus in kPa", "[server][diagnosis]") {
    protocol::TestScheme scheme;
    scheme.specimen.diameter_m = 0.05;
    scheme.effects.membrane_thickness_m = 0.4e-3;
    json report = {
        {"parameters", {{{"name", "friction"}, {"unit", ""}, {"value", 0.5}, {"std", 0.01}},
                        {{"name", "membrane_stiffness"}, {"unit", "Pa"}, {"value", 2.0e5}, {"std", 1.0e4}}}},
        {"base_parameters", json::array()},
        {"candidates", {{{"effect", "membrane_compliance"},
                         {"parameters", {{{"name", "membrane_stiffness"}, {"unit", "Pa"}, {"value", 1.0e5}, {"std", 0.0}}}}}}}};
    service::add_membrane_modulus_to_report(report, scheme);
    const auto& km = report["parameters"][1];
    // 2e5 Pa x 0.05 m / (4 x 0.4 mm) = 6250 kPa.
    CHECK(km["scheme_value"].get<double>() == Approx(6250.0));
    CHECK(km["scheme_value"].get<double>() ==
          Approx(1e-3 * protocol::membrane_modulus_for_stiffness_pa(2.0e5, 0.4e-3, 0.05)));
    CHECK(km["scheme_std"].get<double>() == Approx(312.5));
    CHECK(km["scheme_field"] == "/effects/membrane_modulus_kPa");
    CHECK(km["value"].get<double>() == 2.0e5);  // K_m itself is kept
    CHECK_FALSE(report["parameters"][0].contains("scheme_value"));
    CHECK(report["candidates"][0]["parameters"][0]["scheme_value"].get<double>() == Approx(3125.0));

    scheme.effects.membrane_thickness_m = 0.0;  // no membrane to map to: nothing added
    json bare = {{"parameters", {{{"name", "membrane_stiffness"}, {"value", 1.0}}}}};
    service::add_membrane_modulus_to_report(bare, scheme);
    CHECK_FALSE(bare["parameters"][0].contains("scheme_value"));
}
