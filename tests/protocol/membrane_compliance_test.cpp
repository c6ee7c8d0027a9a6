// K_m = 4 E_m t_m / D (protocol/membrane_compliance.hpp): the deviator the protocol adds
// and the modulus a fitted K_m maps to are the same relation.
#include <catch2/catch.hpp>

#include "engine/protocol/membrane_compliance.hpp"

using namespace triax::protocol;

TEST_CASE("membrane compliance: K_m = 4 E_m t_m / D both ways", "[protocol][membrane]") {
    // 1.4 MPa rubber, 0.5 mm thick, 100 mm specimen: K_m = 28 kPa, 280 Pa at 1 % strain.
    CHECK(membrane_hoop_deviator_pa(1.4e6, 0.5e-3, 0.1, 0.01) == Approx(280.0));
    CHECK(membrane_modulus_for_stiffness_pa(28.0e3, 0.5e-3, 0.1) == Approx(1.4e6));
    const double e_m = membrane_modulus_for_stiffness_pa(5.0e3, 0.3e-3, 0.038);
    CHECK(membrane_hoop_deviator_pa(e_m, 0.3e-3, 0.038, 1.0) == Approx(5.0e3));
}
