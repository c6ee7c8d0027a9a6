#pragma once
// A DEM shear curve's readings averaged over a strain window that grows with the strain,
// before it is compared with a lab's curve. One packing's q(eps) carries slip events
// (force chains buckling and rebuilding) of 10-20 % of q over fractions of a percent of
// strain, which differ from packing to packing while its peak strength does not (reduced
// specimen, ~200 grains, mu 0.3: phi_peak 24.8-26.0 deg over 6 seeds, q at fixed strains
// 11-28 % CV; docs/diagnosis.md section 6). A lab's specimen holds orders of magnitude more
// grains and averages them out. Each reading becomes a triangle-weighted straight-line fit
// of the readings within +-kRelativeHalfWidth of its strain, read at that strain, so the
// small-strain stiffness keeps its resolution, the large-strain plateau loses its packing
// noise, and a straight stretch stays straight (also where the window is cut at the end).
#include <vector>

namespace triax::diagnose {

inline constexpr double kRelativeHalfWidth = 0.2;  // half window / axial strain

// y at each strain x (ascending), fitted over |x' - x| < kRelativeHalfWidth x with weights
// 1 - |x' - x| / (kRelativeHalfWidth x); readings at x <= 0, and any whose window holds
// no other reading, are kept as they are.
std::vector<double> smooth_over_relative_strain(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace triax::diagnose
