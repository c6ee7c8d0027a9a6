#pragma once
// Physical-time increments of a creep stage: geometric growth from `first` by `growth`,
// capped at `max_step`, the last one trimmed to end exactly at `duration`. Log-spaced
// readings like a lab's, and affordable for days: a 2.5-day stage with first = 1 s,
// growth 1.25, cap 1 h has about 90 increments.
#include <algorithm>
#include <vector>

namespace triax::creep {

inline std::vector<double> creep_time_increments(double duration, double first, double growth, double max_step) {
    std::vector<double> dts;
    double t = 0.0, dt = first;
    while (t < duration * (1.0 - 1e-12)) {
        const double step = std::min({dt, max_step, duration - t});
        dts.push_back(step);
        t += step;
        dt *= growth;
    }
    return dts;
}

}  // namespace triax::creep
