#pragma once
// Adaptive gain of a stress-controlled platen (creep holds).
//
// The servo's base gain assumes the skeleton stiffness of a consolidated specimen
// (8 kn per platen); near failure (S = 0.6-0.8) the tangent stiffness is many times
// lower, so each chunk closes only a sliver of the stress error and a hold took up to
// 20,000 cycles (docs/engine.md, "Performance of the full-size paper group"). A fixed
// larger gain makes the stiff early stages oscillate. So the gain adapts: it grows while
// the error keeps its sign and shrinks by less than half per chunk (the platen is too
// timid for this stiffness), and halves whenever the error changes sign (overshoot).
// It never drops below the base gain, so a stiff specimen is held exactly as before.
#include <algorithm>
#include <cmath>

namespace triax::protocol {

class AdaptiveServoGain {
public:
    explicit AdaptiveServoGain(double max_boost = 16.0) : max_boost_(max_boost) {}

    // Factor on the base gain for the chunk that starts with stress error `error` (Pa).
    double update(double error) {
        if (have_previous_) {
            if (error * previous_ < 0.0)
                boost_ = std::max(1.0, 0.5 * boost_);
            else if (std::abs(error) > 0.5 * std::abs(previous_))
                boost_ = std::min(max_boost_, 1.5 * boost_);
        }
        previous_ = error;
        have_previous_ = true;
        return boost_;
    }
    double boost() const { return boost_; }

    // No overshoot: caps the boost so that one chunk closes at most `max_closing` of the
    // error on the specimen's measured tangent stiffness. closing_per_boost: the share of
    // the error the base gain closed in the last chunk (stress change / error at its
    // start); <= 0 when it cannot be measured (no cap).
    double cap(double closing_per_boost, double max_closing = 0.35) {
        if (closing_per_boost > 0.0) boost_ = std::max(1.0, std::min(boost_, max_closing / closing_per_boost));
        return boost_;
    }

private:
    double max_boost_;
    double boost_ = 1.0;
    double previous_ = 0.0;
    bool have_previous_ = false;
};

}  // namespace triax::protocol
