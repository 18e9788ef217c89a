// Linear elasticity as a const law (see material/law_result.hpp for the Voigt convention).
#pragma once
#include "material/elastic/elastic.hpp"
#include "material/law_result.hpp"

namespace skred {

// C of d_sigma = C d_eps (Thesis eq. 2.5) as d sigma[i] / d deps[j] with tensor shear strains:
// lambda on the normal 3 x 3 block, plus 2G on the whole diagonal (shear included).
inline Mat6 elastic_stiffness(const ElasticConstants& e) {
  Mat6 c = Mat6::Zero();
  c.topLeftCorner<3, 3>().setConstant(e.lambda);
  c.diagonal().array() += e.two_g;
  return c;
}

// The const law: sigma^{k+1} = sigma^k + C : d_eps (Thesis eq. 2.5, the update of
// update_stress for Model::LinearElastic, which leaves the state untouched); tangent C.
inline LawResult elastic_evaluate(const ElasticConstants& e, const Sym3& stress, const Sym3& deps,
                                  const PointState& state, bool want_tangent) {
  LawResult r;
  r.stress = stress + elastic_increment(e, deps);
  r.state = state;
  if (want_tangent) {
    r.tangent = elastic_stiffness(e);
    r.has_tangent = true;
  }
  return r;
}

}  // namespace skred
