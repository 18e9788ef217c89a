// A material: density, elastic constants and a constitutive model. The stress update is a
// pure function of (stress, strain increment, state) -> (stress, state), with no particle,
// grid or parser in its signature. This is the umbrella header other folders include.
//
// One folder per model (material/elastic/, material/mohr_coulomb/ (also Tresca),
// material/von_mises/), each holding the model's parameters (params.hpp), its update (the
// in-place return mapping the solver inlines), its const law with the consistent tangent
// (law.hpp), and its name, description, declared parameter table and strength for the relative
// yield function (info.hpp). Adding a model adds a folder, a Model value and a branch in
// update_stress, evaluate (material/law.hpp) and Material::strength.
#pragma once
#include <string>

#include "core/inline.hpp"
#include "core/types.hpp"
#include "material/elastic/elastic.hpp"
#include "material/elastic/info.hpp"
#include "material/mohr_coulomb/info.hpp"
#include "material/mohr_coulomb/mohr_coulomb.hpp"
#include "material/mohr_coulomb/params.hpp"
#include "material/state.hpp"
#include "material/von_mises/info.hpp"
#include "material/von_mises/params.hpp"
#include "material/von_mises/von_mises.hpp"

namespace skred {

enum class Model { LinearElastic, MohrCoulomb, Tresca, VonMises };

struct Material {
  std::string name;
  Model model = Model::LinearElastic;
  double density = 0.0;  // rho_0 [kg/m^3]
  ElasticParams elastic;
  ElasticConstants elastic_constants;           // derived from `elastic` by prepare()
  MohrCoulombParams mohr_coulomb;               // MohrCoulomb and Tresca (friction = dilation = 0)
  MohrCoulombConstants mohr_coulomb_constants;  // derived by prepare()
  VonMisesParams von_mises;                     // VonMises
  // LinearElastic only: the stress of the hyperelastic law of F (solver.elastic_update =
  // "hyperelastic", stress_update.hpp) instead of the incremental update of Thesis eq. 4.1-4.4.
  bool hyperelastic = false;

  // Computes the derived constants; call after setting the parameters.
  void prepare() {
    elastic_constants = ElasticConstants(elastic);
    if (model == Model::Tresca) mohr_coulomb.friction = mohr_coulomb.dilation = 0.0;
    mohr_coulomb_constants = MohrCoulombConstants(mohr_coulomb);
  }

  // P-wave speed used for the CFL time step.
  double wave_speed() const { return std::sqrt(elastic.constrained_modulus() / density); }

  bool plastic() const { return model != Model::LinearElastic; }
  // The model's strength for the relative yield function (Post eq. 66), from its folder.
  MaterialStrength strength() const {
    switch (model) {
      case Model::LinearElastic: return linear_elastic_strength();
      case Model::MohrCoulomb: return mohr_coulomb_strength(mohr_coulomb);
      case Model::Tresca: return tresca_strength(mohr_coulomb);
      case Model::VonMises: return von_mises_strength(von_mises);
    }
    return {};
  }
  // Friction angle [rad] and cohesion [Pa] of the Mohr-Coulomb envelope that describes the
  // strength (Tresca and von Mises: phi = 0 and the peak cohesion); NaN when elastic.
  double friction_angle() const { return strength().friction; }
  double strength_cohesion() const { return strength().cohesion; }
  // Name, description and declared parameters of the model (its folder's info.hpp).
  const ModelInfo& info() const {
    switch (model) {
      case Model::MohrCoulomb: return kMohrCoulombInfo;
      case Model::Tresca: return kTrescaInfo;
      case Model::VonMises: return kVonMisesInfo;
      case Model::LinearElastic: break;
    }
    return kLinearElasticInfo;
  }
};

// Updates `stress` by the strain increment `deps` (Thesis eq. 4.2-4.3: S^{k+1} = sigma^k +
// C : d_eps, then the model's return, eq. 5.2-5.4) and returns the plastic strain increment
// (zero when the step is elastic). `state` is updated by the plastic models; the linear
// elastic model leaves it untouched.
SKRED_INLINE Sym3 update_stress(const Material& m, Sym3& stress, const Sym3& deps, PointState& state) {
  switch (m.model) {
    case Model::LinearElastic:  // no state: an elastic point never yields
      stress += elastic_increment(m.elastic_constants, deps);
      return Sym3::Zero();
    case Model::MohrCoulomb:
    case Model::Tresca:
      return mohr_coulomb_update(m.elastic_constants, m.mohr_coulomb_constants, stress, deps, state);
    case Model::VonMises: return von_mises_update(m.elastic_constants, m.von_mises, stress, deps, state);
  }
  return Sym3::Zero();
}

}  // namespace skred
