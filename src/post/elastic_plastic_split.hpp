// The multiplicative split F = Fe Fp (Post §7.4, eq. 67-77), as pure functions. The solver
// keeps Fe per material point, starting from Fe = I, and calls update_elastic_F() with the
// elastic part of each step's strain increment, which the return mapping of the material
// gives (eq. 70-71: d_eps = d_eps_e + d_eps_p; an elastic step has d_eps_e = d_eps).
// Tensors are 3D: in plane strain the out-of-plane elastic strain is not zero once the point
// has yielded, so Fe_zz != 1 in general. Embed a 2D F with deformation3() (strain_measures.hpp).
#pragma once
#include "core/types.hpp"
#include "material/elastic.hpp"

namespace skred {

// Elastic deformation-gradient increment dFe = d_eps_e + I (Post eq. 69/72). It is symmetric:
// the memo follows Lubarda in letting the elastic unloading take place without rotation, so
// any rigid rotation of the point ends up in Fp.
Mat3 elastic_F_increment(const Sym3& elastic_strain_increment);

// Fe^{k+1} = dFe Fe^k (Post eq. 73).
Mat3 update_elastic_F(const Mat3& Fe, const Sym3& elastic_strain_increment);

// Fp^{k+1} = (Fe^{k+1})^{-1} F^{k+1} (Post eq. 74), so that F = Fe Fp (eq. 67).
Mat3 plastic_F(const Mat3& Fe, const Mat3& F);

// Elastic engineering strain relative to the reference state, eps_e = Fe - I (Post eq. 75),
// taking the symmetric part of Fe (the product of symmetric increments is symmetric only to
// first order).
Sym3 elastic_strain_from_F(const Mat3& Fe);

// Stress recomputed from Fe for linear elasticity: sigma = sigma_initial + E : (Fe - I)
// (Post eq. 75-77), E the isotropic elasticity tensor of `elastic`.
Sym3 stress_from_elastic_F(const Sym3& sigma_initial, const Mat3& Fe, const ElasticConstants& elastic);

}  // namespace skred
