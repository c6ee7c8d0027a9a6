#pragma once
// Membrane compliance (a test artefact): the rubber membrane carries hoop tension, so the
// deviator a lab measures is the soil's plus K_m eps_a, with the membrane's stiffness
//     K_m = 4 E_m t_m / D   (Pa; ASTM D4767 / D7181 form)
// from its modulus E_m (Pa), thickness t_m (m) and the specimen diameter D (m). The
// protocol adds it to q (triaxial_shear.cpp); a diagnosis fits K_m and a scheme takes E_m
// (server/diagnoses/model_schemes.cpp). The relation is stated here only.

namespace triax::protocol {

// Added deviator (Pa, compression positive) at axial strain eps_a [-]: K_m eps_a.
inline double membrane_hoop_deviator_pa(double modulus_pa, double thickness_m, double diameter_m, double axial_strain) {
    return 4.0 * modulus_pa * thickness_m * axial_strain / diameter_m;
}

// The membrane modulus E_m (Pa) that gives the stiffness K_m (Pa): E_m = K_m D / (4 t_m).
inline double membrane_modulus_for_stiffness_pa(double stiffness_pa, double thickness_m, double diameter_m) {
    return stiffness_pa * diameter_m / (4.0 * thickness_m);
}

}  // namespace triax::protocol
