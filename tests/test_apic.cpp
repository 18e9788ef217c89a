// APIC's affine velocity (Jiang et al. 2015; src/transfer/velocity_filters.hpp,
// apic_affine_velocity): the published properties of its transfers, checked on random points
// and random nodal velocities.
// - An affine nodal field v_i = A x_i + b comes back as v_p = A x_p + b and C_p = A for every
//   kernel, also on a clamped B-spline's walls.
// - A g2p then p2g round trip keeps angular momentum: with C_p = B_p D_p^-1 (Jiang's eq. 8-9)
//   sum_i x_i x m_i v_i after equals sum_i x_i x m_i v_i before, for any kernel. skred takes that
//   form for the cubic B-spline; the linear kernel's gradient form is the same C_p; GIMP's is not
//   (the issue lets GIMP keep it), and its loss is printed, not asserted.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "shape/interpolation.hpp"
#include "transfer/scatter.hpp"
#include "transfer/velocity_filters.hpp"

using namespace skred;

namespace {

template <int D>
Eigen::Vector3d cross(const Vec<D>& a, const Vec<D>& b) {
  Eigen::Vector3d A = Eigen::Vector3d::Zero(), B = Eigen::Vector3d::Zero();
  A.head<D>() = a;
  B.head<D>() = b;
  return A.cross(B);
}

template <int D>
GridGeometry<D> unit_grid(bool bspline) {
  GridGeometry<D> g;
  g.h = 0.1;
  for (int d = 0; d < D; ++d) g.cells[d] = 8;
  g.bspline_dofs = bspline;
  return g;
}

// Random points over the whole grid (a B-spline's reach its walls; the others stay a cell and a
// half inside, where their stencils fit), with points exactly on the B-spline's walls too.
template <int D>
std::vector<Vec<D>> points(const GridGeometry<D>& g, std::mt19937& rng, int n) {
  const double margin = g.bspline_dofs ? 0.0 : 1.5 * g.h;
  std::uniform_real_distribution<double> u(margin, g.h * g.cells[0] - margin);
  std::vector<Vec<D>> x(n);
  for (auto& p : x)
    for (int d = 0; d < D; ++d) p[d] = u(rng);
  if (g.bspline_dofs) {
    x[0].setZero();                      // a corner
    x[1].setConstant(g.h * g.cells[0]);  // the opposite corner
    x[2][0] = 0.0;                       // a wall
  }
  return x;
}

// The smallest diagonal entry of D_p = sum_i N_ip (x_i - x_p)(x_i - x_p)^T, node by node.
template <int D, class Shape>
double inertia_min(const Shape& sh, const GridGeometry<D>& g, const NodeStrides<D>& strides,
                   const Vec<D>& x) {
  Mat<D> Dp = Mat<D>::Zero();
  for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
    const Vec<D> r = g.node_position(i) - x;
    Dp += w * r * r.transpose();
  });
  return Dp.diagonal().minCoeff();
}

// The worst |C_p - A| over the points for v_i = A x_i + b, as a share of its round-off bound (1e-13
// plus the positions' share below), and the angular momentum of a round
// trip: { |L_after - L_before| / sum_i m_i |x_i| |v_i| }.
template <int D, class K>
std::pair<double, double> apic_round_trip(const K& kernel, bool bspline, unsigned seed) {
  std::mt19937 rng(seed);
  const GridGeometry<D> g = unit_grid<D>(bspline);
  const NodeStrides<D> strides(g);
  const std::vector<Vec<D>> x = points(g, rng, 60);
  const std::size_t n = x.size(), nodes = g.node_count();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> mp(n);
  std::vector<typename K::Shape> sh(n);
  for (std::size_t p = 0; p < n; ++p) {
    mp[p] = 1.0 + 0.5 * u(rng);
    EXPECT_TRUE(kernel.shape(g, x[p], Vec<D>::Constant(g.h / 4), Mat<D>::Identity(), sh[p]));
  }
  GridArray<double> m(nodes);
  GridArray<Vec<D>> v(nodes), mom(nodes);
  for (std::size_t p = 0; p < n; ++p) scatter(sh[p], strides, mp[p], m.data());

  Mat<D> A = Mat<D>::NullaryExpr([&] { return u(rng); });
  const Vec<D> b = Vec<D>::NullaryExpr([&] { return u(rng); });
  for (std::size_t i = 0; i < nodes; ++i) v[i] = A * g.node_position(i) + b;
  double vmax = 0.0;
  for (std::size_t i = 0; i < nodes; ++i) vmax = std::max(vmax, v[i].norm());
  const double eps = std::numeric_limits<double>::epsilon();
  double affine_error = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    affine_error = std::max(affine_error, (gather(sh[p], strides, v.data()) - (A * x[p] + b)).norm());
    // C_p = B_p D_p^-1 cannot be more exact than the positions: x_i - x_p carries eps |x| of
    // round-off, which D_p^-1 multiplies where a point nears a clamped wall (D_p -> 0). Relative to
    // that bound, the error must be round-off.
    const double bound = 1e-13 + 8.0 * eps * g.h * g.cells[0] * vmax / inertia_min(sh[p], g, strides, x[p]);
    const double e = (apic_affine_velocity<K>(sh[p], g, strides, x[p], v.data()) - A).norm();
    affine_error = std::max(affine_error, e / bound);
  }

  Eigen::Vector3d before = Eigen::Vector3d::Zero(), after = Eigen::Vector3d::Zero();
  double scale = 0.0;
  for (std::size_t i = 0; i < nodes; ++i) {
    v[i] = Vec<D>::NullaryExpr([&] { return u(rng); });
    if (m[i] <= 0.0) continue;
    before += m[i] * cross<D>(g.node_position(i), v[i]);
    scale += m[i] * g.node_position(i).norm() * v[i].norm();
  }
  for (std::size_t p = 0; p < n; ++p) {
    const Vec<D> vp = gather(sh[p], strides, v.data());
    const Mat<D> C = apic_affine_velocity<K>(sh[p], g, strides, x[p], v.data());
    scatter_affine(sh[p], g, strides, x[p], mp[p], vp, C, mom.data());
  }
  for (std::size_t i = 0; i < nodes; ++i) after += cross<D>(g.node_position(i), mom[i]);
  return {affine_error, (after - before).norm() / scale};
}

template <int D>
void check_kernels() {
  for (unsigned seed : {1u, 2u, 3u}) {
    const auto linear = apic_round_trip<D>(LinearKernel<D>{}, false, seed);
    const auto bspline = apic_round_trip<D>(BsplineKernel<D>{}, true, seed);
    const auto gimp = apic_round_trip<D>(GimpKernel<D>{}, false, seed);
    const auto quadrature = apic_round_trip<D>(GimpQuadratureKernel<D, 2>{}, false, seed);
    std::printf(
        "APIC %dD, seed %u: |C_p - A| over its round-off bound: linear %.1e, bspline %.1e, gimp %.1e, "
        "quadrature %.1e; "
        "round trip's angular momentum change: linear %.1e, bspline %.1e, gimp %.1e (gradient form), "
        "quadrature %.1e\n",
        D, seed, linear.first, bspline.first, gimp.first, quadrature.first, linear.second, bspline.second,
        gimp.second, quadrature.second);
    for (const auto& r : {linear, bspline, gimp, quadrature}) EXPECT_LT(r.first, 1.0);
    EXPECT_LT(linear.second, 1e-14);
    EXPECT_LT(bspline.second, 1e-14);
    // The gradient form on GIMP does lose some: this guards that the check above can fail.
    EXPECT_GT(gimp.second, 1e-6);
  }
}

}  // namespace

TEST(Apic, AffineFieldsAndTheRoundTripsAngularMomentum2D) { check_kernels<2>(); }
TEST(Apic, AffineFieldsAndTheRoundTripsAngularMomentum3D) { check_kernels<3>(); }
