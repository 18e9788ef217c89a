// The interpolation kernels a scenario can choose (Thesis §2.3, §3.3), and the dispatch from
// that choice to a kernel type: every solver and transfer is written once per kernel type.
#pragma once
#include "shape/bspline.hpp"
#include "shape/gimp.hpp"
#include "shape/gimp_quadrature.hpp"
#include "shape/linear.hpp"

namespace skred {

enum class Interpolation { Linear, Gimp, GimpQuadrature, Bspline };

inline const char* to_string(Interpolation i) {
  switch (i) {
    case Interpolation::Linear: return "linear";
    case Interpolation::Gimp: return "gimp";
    case Interpolation::GimpQuadrature: return "gimp-quadrature";
    case Interpolation::Bspline: return "bspline";
  }
  return "?";
}

// f(kernel) with the kernel of `interpolation` as a type (quadrature_points: 1, 2 or 3 Gauss
// points per direction, GimpQuadrature only).
template <int D, class F>
decltype(auto) with_kernel(Interpolation interpolation, int quadrature_points, F&& f) {
  switch (interpolation) {
    case Interpolation::Linear: return f(LinearKernel<D>{});
    case Interpolation::Gimp: return f(GimpKernel<D>{});
    case Interpolation::Bspline: return f(BsplineKernel<D>{});
    case Interpolation::GimpQuadrature:
      if (quadrature_points == 1) return f(GimpQuadratureKernel<D, 1>{});
      if (quadrature_points == 3) return f(GimpQuadratureKernel<D, 3>{});
      return f(GimpQuadratureKernel<D, 2>{});
  }
  return f(GimpKernel<D>{});
}

}  // namespace skred
