// A material: density, elastic constants and a constitutive model. The stress update is a
// pure function of (stress, strain increment, state) -> (stress, state), with no particle,
// grid or parser in its signature. Plastic models (Mohr-Coulomb, Tresca, von Mises) add a
// Model value, a parameter block and a branch in update_stress, and nothing else.
#pragma once
#include <string>

#include "core/types.hpp"
#include "material/elastic.hpp"
#include "material/mohr_coulomb.hpp"
#include "material/plastic_params.hpp"
#include "material/state.hpp"
#include "material/von_mises.hpp"

namespace skred {

enum class Model { LinearElastic, MohrCoulomb, Tresca, VonMises };

struct Material {
  std::string name;
  Model model = Model::LinearElastic;
  double density = 0.0;  // rho_0 [kg/m^3]
  ElasticParams elastic;
  ElasticConstants elastic_constants;  // derived from `elastic` by prepare()
  MohrCoulombParams mohr_coulomb;       // MohrCoulomb and Tresca (friction = dilation = 0)
  MohrCoulombConstants mohr_coulomb_constants;  // derived by prepare()
  VonMisesParams von_mises;             // VonMises

  // Computes the derived constants; call after setting the parameters.
  void prepare() {
    elastic_constants = ElasticConstants(elastic);
    if (model == Model::Tresca) mohr_coulomb.friction = mohr_coulomb.dilation = 0.0;
    mohr_coulomb_constants = MohrCoulombConstants(mohr_coulomb);
  }

  // P-wave speed used for the CFL time step.
  double wave_speed() const { return std::sqrt(elastic.constrained_modulus() / density); }

  bool plastic() const { return model != Model::LinearElastic; }
  // Friction angle [rad] and cohesion [Pa] of the Mohr-Coulomb envelope that describes the
  // strength (Tresca and von Mises: phi = 0 and the peak cohesion); NaN when elastic.
  double friction_angle() const {
    return model == Model::MohrCoulomb ? mohr_coulomb.friction : plastic() ? 0.0 : NAN;
  }
  double strength_cohesion() const {
    switch (model) {
      case Model::MohrCoulomb:
      case Model::Tresca: return mohr_coulomb.cohesion;
      case Model::VonMises: return von_mises.cohesion_peak;
      case Model::LinearElastic: break;
    }
    return NAN;
  }
};

// Updates `stress` by the strain increment `deps` (Thesis eq. 4.2-4.3: S^{k+1} = sigma^k +
// C : d_eps, then the model's return, eq. 5.2-5.4) and returns the plastic strain increment
// (zero when the step is elastic). `state` is updated by the plastic models; the linear
// elastic model leaves it untouched.
[[gnu::always_inline]] inline Sym3 update_stress(const Material& m, Sym3& stress, const Sym3& deps,
                                                 PointState& state) {
  switch (m.model) {
    case Model::LinearElastic:  // no state: an elastic point never yields
      stress += elastic_increment(m.elastic_constants, deps);
      return Sym3::Zero();
    case Model::MohrCoulomb:
    case Model::Tresca:
      return mohr_coulomb_update(m.elastic_constants, m.mohr_coulomb_constants, stress, deps, state);
    case Model::VonMises:
      return von_mises_update(m.elastic_constants, m.von_mises, stress, deps, state);
  }
  return Sym3::Zero();
}

}  // namespace skred
