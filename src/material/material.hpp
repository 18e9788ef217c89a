// A material: density, elastic constants and a constitutive model. The stress update is a
// pure function of (stress, strain increment, state) -> (stress, state), with no particle,
// grid or parser in its signature. Plastic models (Mohr-Coulomb, Tresca, von Mises) add a
// Model value, a parameter block and a branch in update_stress, and nothing else.
#pragma once
#include <string>

#include "core/types.hpp"
#include "material/elastic.hpp"
#include "material/plastic_params.hpp"
#include "material/state.hpp"

namespace skred {

enum class Model { LinearElastic, MohrCoulomb, Tresca, VonMises };

struct Material {
  std::string name;
  Model model = Model::LinearElastic;
  double density = 0.0;  // rho_0 [kg/m^3]
  ElasticParams elastic;
  ElasticConstants elastic_constants;  // derived from `elastic` by prepare()
  MohrCoulombParams mohr_coulomb;       // MohrCoulomb and Tresca (friction = dilation = 0)
  VonMisesParams von_mises;             // VonMises

  // Computes the derived constants; call after setting the parameters.
  void prepare() { elastic_constants = ElasticConstants(elastic); }

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
// C : d_eps) and returns the plastic work dissipated per unit volume (zero when elastic).
[[gnu::always_inline]] inline double update_stress(const Material& m, Sym3& stress, const Sym3& deps,
                                                   PointState& state) {
  switch (m.model) {
    case Model::LinearElastic:
      stress += elastic_increment(m.elastic_constants, deps);
      state.yielding = 0;
      return 0.0;
  }
  return 0.0;
}

}  // namespace skred
