#include "engine/protocol/platen_servo.hpp"

#include "engine/protocol/specimen.hpp"

namespace triax::protocol {

PlatenServo PlatenServo::for_specimen(const Specimen& sp) {
    PlatenServo s;
    s.k_skeleton_n_m = sp.soil_kn() * 8.0;  // about 8 contacts under a grain
    s.v_max_m_s = 0.05 * sp.height() / (2000.0 * sp.world().time_step());
    return s;
}

}  // namespace triax::protocol
