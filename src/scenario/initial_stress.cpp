#include "scenario/initial_stress.hpp"

#include <algorithm>
#include <cmath>

namespace skred {

double k0_of(const InitialStress& is, const Material& m) {
  const double nu = m.elastic.poisson;
  switch (is.rule) {
    case K0Rule::None: return 0.0;
    case K0Rule::Poisson: return nu / (1.0 - nu);                      // Thesis eq. 5.7
    case K0Rule::Jaky:                                                  // Post eq. 51
      return m.model == Model::MohrCoulomb ? 1.0 - std::sin(m.mohr_coulomb.friction) : nu / (1.0 - nu);
    case K0Rule::Value: return is.k0;
  }
  return 0.0;
}

void apply_initial_stress(const Scenario& s, Particles<2>& P) {
  if (s.initial_stress.rule == K0Rule::None || P.size() == 0) return;
  const double g = std::abs(s.gravity[1]);
  const std::size_t n = P.size();
  // Columns of width b (the finest point spacing); a point loads every column its voxel covers.
  double b = INFINITY;
  for (std::size_t p = 0; p < n; ++p) b = std::min(b, 2.0 * P.half0[p][0]);
  const auto column = [&](double x) { return static_cast<long>(std::floor((x - s.origin[0]) / b)); };
  long cols = column(s.origin[0] + s.cells[0] * s.cell_size) + 1;
  std::vector<std::vector<std::size_t>> members(static_cast<std::size_t>(cols));
  for (std::size_t p = 0; p < n; ++p) {
    const long lo = column(P.x[p][0] - P.half0[p][0] + 0.5 * b);
    const long hi = column(P.x[p][0] + P.half0[p][0] - 0.5 * b);
    for (long c = std::max(0L, lo); c <= std::min(cols - 1, hi); ++c)
      members[static_cast<std::size_t>(c)].push_back(p);
  }
  std::vector<double> overburden(n, 0.0);  // weight per unit width above the point [Pa]
  for (long c = 0; c < cols; ++c) {
    auto& m = members[static_cast<std::size_t>(c)];
    std::sort(m.begin(), m.end(), [&](std::size_t a, std::size_t d) { return P.x[a][1] > P.x[d][1]; });
    double above = 0.0;
    for (std::size_t p : m) {
      const double w = P.mass[p] * g / (2.0 * P.half0[p][0]);  // weight per unit width
      if (column(P.x[p][0]) == c) overburden[p] = above + 0.5 * w;  // the point's own column
      above += w;
    }
  }
  for (std::size_t p = 0; p < n; ++p) {
    const double syy = -overburden[p];  // Thesis eq. 5.6
    const double k0 = k0_of(s.initial_stress, s.materials[static_cast<std::size_t>(P.material[p])]);
    P.stress[p].setZero();
    P.stress[p][0] = k0 * syy;  // Thesis eq. 5.7
    P.stress[p][1] = syy;
    P.stress[p][2] = k0 * syy;
  }
  P.set_reference_stress();  // reference state of Fe (Post eq. 77)
}

std::vector<Material> stage_materials(const Scenario& s, const Stage& stage) {
  std::vector<Material> mats = s.materials;
  for (const MaterialOverride& o : stage.overrides) {
    Material& m = mats[static_cast<std::size_t>(o.material)];
    if (o.friction) m.mohr_coulomb.friction = *o.friction;
    if (o.dilation) m.mohr_coulomb.dilation = *o.dilation;
    if (o.cohesion) {
      if (m.model == Model::VonMises) {
        m.von_mises.cohesion_residual *= *o.cohesion / m.von_mises.cohesion_peak;
        m.von_mises.cohesion_peak = *o.cohesion;
      } else {
        m.mohr_coulomb.cohesion = *o.cohesion;
      }
    }
  }
  const double f = stage.strength_reduction;
  for (Material& m : mats) {
    if (f != 1.0) {
      m.mohr_coulomb.cohesion /= f;
      m.mohr_coulomb.friction = std::atan(std::tan(m.mohr_coulomb.friction) / f);
      m.mohr_coulomb.dilation = std::atan(std::tan(m.mohr_coulomb.dilation) / f);
      m.von_mises.cohesion_peak /= f;
      m.von_mises.cohesion_residual /= f;
    }
    if (stage.elastic) m.model = Model::LinearElastic;
    m.prepare();
  }
  return mats;
}

}  // namespace skred
