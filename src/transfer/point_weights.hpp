// Every point's weighting functions N_ip and gradients (Thesis eq. 2.46-2.47, 3.14-3.15) of
// the current step, evaluated once by the map that starts the step and read by every later
// transfer of the step (the explicit phases; the implicit integrator keeps its own,
// implicit/point_stencils.hpp). The stored form follows the kernel (K::Packed).
#pragma once
#include <cstddef>
#include <variant>
#include <vector>

#include "core/huge_pages.hpp"
#include "shape/interpolation.hpp"

namespace skred {

template <int D>
class PointWeights {
 public:
  // The stored weights of kernel K for n points (resized only when n changes).
  template <class K>
  typename K::Packed* get(std::size_t n) {
    using Store = std::vector<typename K::Packed>;
    if (!std::holds_alternative<Store>(store_)) store_.template emplace<Store>();
    Store& s = std::get<Store>(store_);
    if (s.size() != n) {
      reserve_huge(s, n);
      s.resize(n);
    }
    return s.data();
  }

 private:
  std::variant<std::monostate, std::vector<typename LinearKernel<D>::Packed>,
               std::vector<typename GimpKernel<D>::Packed>, std::vector<typename BsplineKernel<D>::Packed>,
               std::vector<QuadratureState<D>>>
      store_;
};

}  // namespace skred
