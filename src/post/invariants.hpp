// Stress invariants for plotting (Post §7.2) and the relative yield function (Post eq. 66).
// Stresses are Voigt [xx, yy, zz, xy, yz, xz], tension positive, as everywhere in skred.
#pragma once
#include "core/types.hpp"

namespace skred {

// Principal stresses ordered sigma_1 <= sigma_2 <= sigma_3 (the memo's and eq. 45's order:
// sigma_1 is the most compressive).
struct PrincipalStresses {
  double s1 = 0.0, s2 = 0.0, s3 = 0.0;
};

// For a plane stress state (yz = xz = 0, every 2D run) the in-plane pair comes from Post
// eq. 59, sigma = (xx + yy)/2 +- sqrt(((xx - yy)/2)^2 + xy^2), and the out-of-plane stress zz
// is the third; the three are then sorted. A general 3D state uses an eigen-decomposition.
PrincipalStresses principal_stresses(const Sym3& s);

// In-plane principal direction (Post eq. 60): the angle in degrees, in (-90, 90], from the
// x axis (counter-clockwise) to the direction of the larger in-plane principal stress,
// theta = atan2(2 xy, xx - yy) / 2. The memo prints eq. 60 with the fraction upside down;
// tan 2 theta = 2 xy / (xx - yy) is the condition for zero shear stress on the rotated axes.
// Equal in-plane principal stresses (xx = yy, xy = 0) have every direction principal; the
// function returns 0 for them.
double principal_angle_degrees(const Sym3& s);

// Mean stress p = (sigma_1 + sigma_2 + sigma_3)/3 (Post eq. 61).
double mean_stress_p(const PrincipalStresses& ps);

// Deviatoric stress q = sqrt(((s1 - s2)^2 + (s2 - s3)^2 + (s1 - s3)^2)/2) (Post eq. 62), the
// same as sqrt(3 J2) (deviatoric_stress in core/types.hpp).
double deviatoric_stress_q(const PrincipalStresses& ps);

// Relative yield function (Post eq. 66) of the Mohr-Coulomb criterion of eq. 45:
//   f_rel = (sigma_3 - sigma_1)/2 / (c cos(phi) - (sigma_1 + sigma_3)/2 sin(phi)),
// the mobilised shear radius over the radius available at the same centre: 0 for a
// hydrostatic state, 1 on the yield surface (f = 0 in eq. 45). The memo's printed eq. 66 has
// lost the sin(phi) factor; without it f_rel = 1 would not be the yield surface (with phi = 0,
// Tresca, the two agree up to sign). friction is phi in radians, cohesion c in Pa.
// Returns NaN if friction or cohesion is NaN (a material without strength), and +inf when the
// denominator is <= 0 with shear present, i.e. the stress lies beyond the apex of the cone
// (mean tension above c cot(phi)), where no shear strength is left; a hydrostatic state
// there gives +inf as well, since it is beyond the strength envelope.
double relative_yield(const Sym3& s, double friction, double cohesion);

}  // namespace skred
