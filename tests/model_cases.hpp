// The materials the random-state tests of the stress update run through: every model, with the
// Mohr-Coulomb variants whose paths differ (tension cut-off, dilation cut-off).
#pragma once
#include <numbers>
#include <vector>

#include "material/material.hpp"

namespace skred::test {

inline Material model_base(Model model) {
  Material m;
  m.model = model;
  m.density = 2000.0;
  m.elastic = {1e7, 0.3};
  return m;
}

struct NamedModel {
  const char* name;
  Material m;
};

// Prepared; stresses of a few tens of kPa reach their yield surfaces.
inline std::vector<NamedModel> model_cases() {
  constexpr double kPa = 1e3, deg = std::numbers::pi / 180.0;
  std::vector<NamedModel> out;
  out.push_back({"linear-elastic", model_base(Model::LinearElastic)});
  Material mc = model_base(Model::MohrCoulomb);
  mc.mohr_coulomb.friction = 30 * deg;
  mc.mohr_coulomb.cohesion = 10 * kPa;
  mc.mohr_coulomb.dilation = 10 * deg;
  out.push_back({"mohr-coulomb", mc});
  Material mct = mc;
  mct.mohr_coulomb.tension_cutoff = 5 * kPa;
  out.push_back({"mohr-coulomb + tension cut-off", mct});
  Material mcd = mc;
  mcd.mohr_coulomb.initial_void_ratio = 0.6;
  mcd.mohr_coulomb.max_void_ratio = 0.62;  // switch at volume strain ln(1.62/1.6) = 0.0124
  out.push_back({"mohr-coulomb + dilation cut-off", mcd});
  Material tr = model_base(Model::Tresca);
  tr.mohr_coulomb.cohesion = 30 * kPa;
  out.push_back({"tresca", tr});
  Material vm = model_base(Model::VonMises);
  vm.von_mises = {12 * kPa, 3 * kPa, -1e6};
  out.push_back({"von-mises softening", vm});
  for (NamedModel& n : out) n.m.prepare();
  return out;
}

}  // namespace skred::test
