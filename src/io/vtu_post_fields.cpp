// The post-processing cell fields of the particle VTU (Post §5-7): speed, strain measures,
// principal stresses and direction, relative yield, and the elastic-plastic split.
#include <Eigen/LU>

#include "io/vtu_blocks.hpp"
#include "io/vtu_writer.hpp"
#include "post/elastic_plastic_split.hpp"
#include "post/invariants.hpp"
#include "post/strain_measures.hpp"

namespace skred::vtu {

namespace {

inline const Sym3& full(const Sym3& s) { return s; }
inline Sym3 full(const PointStress<2>& s) { return full_stress<2>(s); }
// PointStress<3> is Sym3 itself: the first overload.

// principal_stress (3), principal_angle and, with strength, relative_yield of `stress`
// (Sym3 or the points' stored PointStress<2>).
template <int D, class V>
void add_invariant_blocks(std::vector<Block>& blocks, const std::string& prefix, const std::vector<V>& stress,
                          const Particles<D>& P, const std::vector<MaterialStrength>* strength) {
  blocks.push_back(reals(prefix + "principal_stress", 3,
                         [&stress](std::size_t p, double* o) {
                           const PrincipalStresses ps =
                               principal_stresses(Sym3(full(stress[p])));  // Post eq. 59
                           return put(put(put(o, ps.s1), ps.s2), ps.s3);
                         },
                         {"s1", "s2", "s3"}));
  blocks.push_back(reals(prefix + "principal_angle", 1, [&stress](std::size_t p, double* o) {
    return put(o, principal_angle_degrees(Sym3(full(stress[p]))));  // Post eq. 60
  }));
  if (!strength) return;
  blocks.push_back(reals(prefix + "relative_yield", 1, [&stress, &P, strength](std::size_t p, double* o) {
    const MaterialStrength& m = (*strength)[P.material[p]];
    return put(o, relative_yield(Sym3(full(stress[p])), m.friction, m.cohesion));
  }));
}

template <int D, class Measure>
Block strain_block(std::string name, const Particles<D>& P, Measure measure) {
  return reals(
      std::move(name), 6,
      [&P, measure](std::size_t p, double* o) { return put_sym3(o, measure(deformation3<D>(P.F[p]))); },
      voigt_names());
}

}  // namespace

template <int D>
void add_post_blocks(std::vector<Block>& blocks, const Particles<D>& P, const ParticleFields& extra) {
  blocks.push_back(reals("speed", 1, [&P](std::size_t p, double* o) { return put(o, P.v[p].norm()); }));
  blocks.push_back(reals(
      "F", 9, [&P](std::size_t p, double* o) { return put_mat3(o, deformation3<D>(P.F[p])); },
      tensor_names()));
  blocks.push_back(strain_block("engineering_strain", P, engineering_strain));  // eq. 63
  blocks.push_back(strain_block("green_strain", P, green_lagrange_strain));     // eq. 64
  blocks.push_back(strain_block("hencky_strain", P, hencky_strain));            // eq. 65
  add_invariant_blocks(blocks, "", P.stress, P, extra.strength);
  if (extra.smoothed_stress)
    add_invariant_blocks(blocks, "smoothed_", *extra.smoothed_stress, P, extra.strength);
  if (extra.elastic_F) {
    const std::vector<Mat3>& Fe = *extra.elastic_F;
    blocks.push_back(reals(
        "Fe", 9, [&Fe](std::size_t p, double* o) { return put_mat3(o, Fe[p]); }, tensor_names()));
    blocks.push_back(reals(
        "Fp", 9,
        [&Fe, &P](std::size_t p, double* o) {
          return put_mat3(o, plastic_F(Fe[p], deformation3<D>(P.F[p])));  // Post eq. 74
        },
        tensor_names()));
  }
  if (extra.stress_from_elastic_F) {
    const std::vector<Sym3>& s = *extra.stress_from_elastic_F;
    blocks.push_back(reals(
        "stress_from_Fe", 6, [&s](std::size_t p, double* o) { return put_sym3(o, s[p]); }, voigt_names()));
  }
}

template void add_post_blocks<2>(std::vector<Block>&, const Particles<2>&, const ParticleFields&);
template void add_post_blocks<3>(std::vector<Block>&, const Particles<3>&, const ParticleFields&);

}  // namespace skred::vtu
