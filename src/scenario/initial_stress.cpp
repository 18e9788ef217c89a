#include "scenario/initial_stress.hpp"

#include <algorithm>
#include <cmath>

namespace skred {

double k0_of(const InitialStress& is, const Material& m) {
  const double nu = m.elastic.poisson;
  switch (is.rule) {
    case K0Rule::None: return 0.0;
    case K0Rule::Poisson: return nu / (1.0 - nu);  // Thesis eq. 5.7
    case K0Rule::Jaky:                             // Post eq. 51
      return m.model == Model::MohrCoulomb ? 1.0 - std::sin(m.mohr_coulomb.friction) : nu / (1.0 - nu);
    case K0Rule::Value: return is.k0;
  }
  return 0.0;
}

// Columns of width b (the finest point spacing) over the horizontal axes: x in 2D, x and z in
// 3D. A point loads every column its voxel covers and is loaded by the column it stands in.
template <int D>
void apply_initial_stress(const ScenarioOf<D>& s, Particles<D>& P) {
  if (s.initial_stress.rule == K0Rule::None || P.size() == 0) return;
  const double g = std::abs(s.gravity[1]);
  const std::size_t n = P.size();
  constexpr int H = D == 2 ? 1 : 2;  // horizontal axes
  constexpr int axis[2] = {0, 2};    // x, then z
  // The columns' width: the smallest points' (of the scenario's bodies, whichever of their
  // points P holds: a process's part of the set-up, run/point_setup.hpp).
  double b = INFINITY;
  for (const BodyOf<D>& body : s.bodies)
    if (body.dilated_from < 0) b = std::min(b, 2.0 * (0.5 * (s.cell_size / body.particles_per_cell)));
  const auto column = [&](int h, double x) {
    return static_cast<long>(std::floor((x - s.origin[axis[h]]) / b));
  };
  long cols[2] = {1, 1};
  for (int h = 0; h < H; ++h)
    cols[h] = column(h, s.origin[axis[h]] + s.cells[static_cast<std::size_t>(axis[h])] * s.cell_size) + 1;
  const auto flat = [&](long cx, long cz) { return static_cast<std::size_t>(cz * cols[0] + cx); };
  std::vector<std::vector<std::size_t>> members(static_cast<std::size_t>(cols[0] * cols[1]));
  for (std::size_t p = 0; p < n; ++p) {
    long lo[2] = {0, 0}, hi[2] = {0, 0};
    for (int h = 0; h < H; ++h) {
      const double x = P.x[p][axis[h]], l = P.half0[p][axis[h]];
      lo[h] = std::max(0L, column(h, x - l + 0.5 * b));
      hi[h] = std::min(cols[h] - 1, column(h, x + l - 0.5 * b));
    }
    for (long cz = lo[1]; cz <= hi[1]; ++cz)
      for (long cx = lo[0]; cx <= hi[0]; ++cx) members[flat(cx, cz)].push_back(p);
  }
  std::vector<double> overburden(n, 0.0);  // weight per unit area above the point [Pa]
  for (long cz = 0; cz < cols[1]; ++cz)
    for (long cx = 0; cx < cols[0]; ++cx) {
      auto& m = members[flat(cx, cz)];
      std::sort(m.begin(), m.end(), [&](std::size_t a, std::size_t d) { return P.x[a][1] > P.x[d][1]; });
      double above = 0.0;
      for (std::size_t p : m) {
        double w = P.mass[p] * g;  // weight per unit width (2D) or area (3D)
        for (int h = 0; h < H; ++h) w /= 2.0 * P.half0[p][axis[h]];
        if constexpr (D == 2)  // axisymmetric: the mass is per radian, m = rho A r
          if (s.geometry == Geometry::Axisymmetric) w /= P.x[p][0];
        const bool own = column(0, P.x[p][0]) == cx && (H == 1 || column(1, P.x[p][axis[1]]) == cz);
        if (own) overburden[p] = above + 0.5 * w;  // the point's own column
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

template void apply_initial_stress<2>(const Scenario&, Particles<2>&);
template void apply_initial_stress<3>(const Scenario3&, Particles<3>&);

double density_at_stage_start(const ScenarioCommon& s, std::size_t k, int m) {
  double rho = s.materials.at(static_cast<std::size_t>(m)).density;
  for (std::size_t j = 0; j < k && j < s.stages.size(); ++j)
    for (const MaterialOverride& o : s.stages[j].overrides)
      if (o.material == m && o.density) rho = *o.density;
  return rho;
}

std::vector<Material> stage_materials(const ScenarioCommon& s, const Stage& stage) {
  std::vector<Material> mats = s.materials;
  for (std::size_t k = 0; k < s.stages.size(); ++k)  // the density the stage reaches
    if (&s.stages[k] == &stage)
      for (std::size_t m = 0; m < mats.size(); ++m)
        mats[m].density = density_at_stage_start(s, k + 1, static_cast<int>(m));
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
