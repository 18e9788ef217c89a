// Initial stresses and the per-stage material table, derived from a parsed scenario.
#pragma once
#include <vector>

#include "core/particles.hpp"
#include "scenario/scenario.hpp"

namespace skred {

// K0 initial stress from the overburden (Thesis eq. 5.6-5.7, Post eq. 50-51):
// sigma_yy = -|g_y| (weight per unit width (2D) or area (3D) of the material above the point,
// plus half its own), sigma_xx = sigma_zz = K0 sigma_yy, no shear. The weight above a point
// is summed over the points of every body whose voxel covers its x (3D: x and z) position,
// so layered bodies of different densities are handled (axisymmetric: each point's mass per
// radian divided by its radius, so the stresses are those of plane strain). Does nothing when
// the rule is None.
template <int D>
void apply_initial_stress(const ScenarioOf<D>& s, Particles<D>& P);

// K0 of a material under a rule (Poisson: nu/(1-nu); Jaky: 1 - sin(phi) for Mohr-Coulomb,
// nu/(1-nu) otherwise; Value: the given number).
double k0_of(const InitialStress& is, const Material& m);

// The material table of a stage: the scenario's materials with the stage's overrides and
// strength reduction applied (c / SRF, tan(phi) / SRF, tan(psi) / SRF), or all held linear
// elastic when the stage says so.
std::vector<Material> stage_materials(const ScenarioCommon& s, const Stage& stage);

}  // namespace skred
