// The fitted test artefacts as a scheme's protocol applies them (diagnose/final_model.hpp).
#include <catch2/catch.hpp>

#include <stdexcept>

#include "engine/diagnose/final_model.hpp"
#include "engine/protocol/membrane_compliance.hpp"

using namespace triax;
using namespace triax::diagnose;

TEST_CASE("fitted artefacts switch on in the scheme as fitted", "[diagnose][artefacts]") {
    protocol::TestScheme s;
    s.specimen.diameter_m = 0.05;
    s.specimen.height_m = 0.1;
    s.effects.membrane_thickness_m = 0.4e-3;
    SECTION("seating strain and membrane stiffness") {
        apply_fitted_artefacts(s, {{"seating_strain", "", 0.004}, {"membrane_stiffness", "", 6.0e3}});
        CHECK(s.effects.seating_error);
        CHECK(s.effects.seating_displacement_m == Approx(0.4e-3));
        CHECK(s.effects.membrane_compliance);
        // The protocol then adds K_m eps_a to q.
        CHECK(protocol::membrane_hoop_deviator_pa(s.effects.membrane_modulus_pa, 0.4e-3, 0.05, 0.01) == Approx(60.0));
    }
    SECTION("absent or zero parameters leave the artefacts off") {
        apply_fitted_artefacts(s, {{"seating_strain", "", 0.0}, {"friction", "", 0.5}});
        CHECK_FALSE(s.effects.seating_error);
        CHECK_FALSE(s.effects.membrane_compliance);
    }
    SECTION("membrane compliance needs a thickness") {
        s.effects.membrane_thickness_m = 0.0;
        CHECK_THROWS_AS(apply_fitted_artefacts(s, {{"membrane_stiffness", "", 6.0e3}}), std::invalid_argument);
    }
}
