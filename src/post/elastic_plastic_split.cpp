#include "post/elastic_plastic_split.hpp"

#include <Eigen/LU>

namespace skred {

Mat3 elastic_F_increment(const Sym3& elastic_strain_increment) {
  return to_matrix(elastic_strain_increment) + Mat3::Identity();  // Post eq. 72
}

Mat3 update_elastic_F(const Mat3& Fe, const Sym3& elastic_strain_increment) {
  return elastic_F_increment(elastic_strain_increment) * Fe;  // Post eq. 73
}

Mat3 plastic_F(const Mat3& Fe, const Mat3& F) {
  return Fe.inverse() * F;  // Post eq. 74 (closed-form 3 x 3 inverse)
}

Sym3 elastic_strain_from_F(const Mat3& Fe) {
  return to_voigt(Fe - Mat3::Identity());  // Post eq. 75 (to_voigt symmetrises)
}

Sym3 stress_from_elastic_F(const Sym3& sigma_initial, const Mat3& Fe, const ElasticConstants& elastic) {
  // Post eq. 76: d_sigma = E : eps_e; eq. 77: sigma = sigma_initial + d_sigma.
  return sigma_initial + elastic_increment(elastic, elastic_strain_from_F(Fe));
}

}  // namespace skred
