// Shape-function invariants for every kernel in 2D and 3D (partition of unity, zero gradient
// sum, exact reproduction of linear fields), quadrature GIMP against analytic GIMP
// (Thesis fig. 3.9-3.10) and the clamped B-spline's behaviour at the walls.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "shape/bspline.hpp"
#include "shape/gimp.hpp"
#include "shape/gimp_quadrature.hpp"
#include "shape/linear.hpp"

using namespace skred;

namespace {

template <int D>
GridGeometry<D> make_grid(bool bspline) {
  GridGeometry<D> g;
  for (int d = 0; d < D; ++d) {
    g.origin[d] = -0.3 * (d + 1);
    g.cells[d] = 7 + d;
  }
  g.h = 0.25;
  g.bspline_dofs = bspline;
  return g;
}

// Checks sum N = 1, sum grad N = 0, sum N x_i = x_p and sum x_i (x) grad N = I.
template <int D, class K>
void check_invariants(const K& kernel, bool bspline, const Mat<D>& F, double margin) {
  const GridGeometry<D> g = make_grid<D>(bspline);
  const StencilOffsets<D, K::S> offsets(g);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec<D> half = Vec<D>::Constant(g.h / 4);
  int evaluated = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = g.origin[d] + margin + u(rng) * (g.h * g.cells[d] - 2 * margin);
    typename K::StencilT st;
    if (!kernel(g, x, half, F, st)) continue;  // a point inside the domain rejected: counted below
    ++evaluated;
    double sw = 0;
    Vec<D> sg = Vec<D>::Zero(), sx = Vec<D>::Zero();
    Mat<D> sgx = Mat<D>::Zero();
    for (int k = 0; k < K::StencilT::size; ++k) {
      const Vec<D> xi = g.node_position(st.base + offsets.off[k]);
      sw += st.w[k];
      sg += st.grad[k];
      sx += st.w[k] * xi;
      sgx += xi * st.grad[k].transpose();
      EXPECT_GE(st.w[k], -1e-14);
    }
    EXPECT_NEAR(sw, 1.0, 1e-13);
    EXPECT_LT(sg.norm(), 1e-11);
    EXPECT_LT((sx - x).norm(), 1e-13);
    EXPECT_LT((sgx - Mat<D>::Identity()).norm(), 1e-11);
  }
  EXPECT_EQ(evaluated, 2000) << "points inside the domain rejected";
}

template <int D>
Mat<D> shear() {
  Mat<D> F = Mat<D>::Identity();
  F(0, 1) = 0.4;
  F(1, 0) = -0.1;
  F(0, 0) = 1.1;
  return F;
}

}  // namespace

TEST(Shape, Linear2D) { check_invariants<2>(LinearKernel<2>{}, false, Mat<2>::Identity(), 0.0); }
TEST(Shape, Linear3D) { check_invariants<3>(LinearKernel<3>{}, false, Mat<3>::Identity(), 0.0); }
TEST(Shape, Gimp2D) { check_invariants<2>(GimpKernel<2>{}, false, Mat<2>::Identity(), 0.0625); }
TEST(Shape, Gimp3D) { check_invariants<3>(GimpKernel<3>{}, false, Mat<3>::Identity(), 0.0625); }
TEST(Shape, GimpFollowsDetF2D) { check_invariants<2>(GimpKernel<2>{}, false, shear<2>(), 0.1); }
TEST(Shape, Bspline2D) { check_invariants<2>(BsplineKernel<2>{}, true, Mat<2>::Identity(), 0.0); }
TEST(Shape, Bspline3D) { check_invariants<3>(BsplineKernel<3>{}, true, Mat<3>::Identity(), 0.0); }
TEST(Shape, Quadrature1x1) { check_invariants<2>(GimpQuadratureKernel<2, 1>{}, false, shear<2>(), 0.1); }
TEST(Shape, Quadrature2x2) { check_invariants<2>(GimpQuadratureKernel<2, 2>{}, false, shear<2>(), 0.1); }
TEST(Shape, Quadrature3x3) { check_invariants<2>(GimpQuadratureKernel<2, 3>{}, false, shear<2>(), 0.1); }
TEST(Shape, Quadrature3D) { check_invariants<3>(GimpQuadratureKernel<3, 2>{}, false, shear<3>(), 0.1); }
// A needle voxel (stretched 12 times along a sheared axis: 6 cells long) is drawn in to fit
// the kernel's block instead of being refused ("left the grid"), keeping every invariant.
TEST(Shape, QuadratureNeedleVoxelIsDrawnIn) {
  Mat<2> F = shear<2>();
  F.col(0) *= 12.0;
  check_invariants<2>(GimpQuadratureKernel<2, 2>{}, false, F, 0.3);
  Mat<3> F3 = shear<3>();
  F3.col(1) *= 12.0;
  check_invariants<3>(GimpQuadratureKernel<3, 2>{}, false, F3, 0.3);
}

// Thesis fig. 3.9-3.10: L = 1, l_p = 1/4 (2 x 2 points per cell). One Gauss point gives the
// linear shape functions; 2x2 and 3x3 approach the analytic GIMP functions, and a voxel
// inside one cell is integrated exactly by 2x2 points.
TEST(Shape, QuadratureConvergesToAnalyticGimp) {
  GridGeometry<2> g;
  g.h = 1.0;
  g.cells = {8, 8};
  const Vec<2> half(0.25, 0.25);
  const StencilOffsets<2, 3> off3(g);
  const StencilOffsets<2, 4> off4(g);
  auto weight_error = [&](auto kernel, double& werr, double& gerr, double& inside_err) {
    werr = gerr = inside_err = 0;
    for (int a = 0; a <= 200; ++a) {
      const Vec<2> x(3.0 + a * 0.01, 4.37);
      GimpKernel<2>::StencilT ref;
      typename decltype(kernel)::StencilT st;
      ASSERT_TRUE(GimpKernel<2>{}(g, x, half, Mat<2>::Identity(), ref));
      ASSERT_TRUE(kernel(g, x, half, Mat<2>::Identity(), st));
      for (int k = 0; k < 16; ++k) {
        const std::size_t node = st.base + off4.off[k];
        double wr = 0;
        Vec<2> gr = Vec<2>::Zero();
        for (int j = 0; j < 9; ++j)
          if (ref.base + off3.off[j] == node) {
            wr = ref.w[j];
            gr = ref.grad[j];
          }
        const double e = std::abs(st.w[k] - wr);
        werr = std::max(werr, e);
        gerr = std::max(gerr, (st.grad[k] - gr).norm());
        const double fx = x[0] - std::floor(x[0]), fy = x[1] - std::floor(x[1]);
        if (fx >= 0.25 && fx <= 0.75 && fy >= 0.25 && fy <= 0.75) inside_err = std::max(inside_err, e);
      }
    }
  };
  double w1, g1, i1, w2, g2, i2, w3, g3, i3;
  weight_error(GimpQuadratureKernel<2, 1>{}, w1, g1, i1);
  weight_error(GimpQuadratureKernel<2, 2>{}, w2, g2, i2);
  weight_error(GimpQuadratureKernel<2, 3>{}, w3, g3, i3);
  std::printf("max |N_quad - N_gimp|: 1pt %.4f  2x2 %.4f  3x3 %.4f; gradient: %.4f %.4f %.4f\n", w1, w2, w3,
              g1, g2, g3);
  EXPECT_GT(w1, w2);
  EXPECT_GT(w2, w3);
  EXPECT_GT(g1, g2);
  EXPECT_GT(g2, g3);
  EXPECT_LT(i2, 1e-14);  // voxel in one cell: 2x2 Gauss points are exact
  EXPECT_LT(w3, 0.02);
}

TEST(Shape, BsplineIsInterpolatoryAtWallsAndSmooth) {
  const int n = 6;
  double w[4], gr[4];
  EXPECT_EQ(bspline_1d(0.0, n, w, gr), 0);
  EXPECT_DOUBLE_EQ(w[0], 1.0);
  EXPECT_DOUBLE_EQ(w[1] + w[2] + w[3], 0.0);
  EXPECT_EQ(bspline_1d(n, n, w, gr), n - 1);
  EXPECT_DOUBLE_EQ(w[3], 1.0);
  // Values and first derivatives are continuous across every cell boundary.
  for (int c = 1; c < n; ++c) {
    double wl[4], gl[4], wr[4], grr[4];
    const int kl = bspline_1d(c - 1e-12, n, wl, gl);
    const int kr = bspline_1d(c + 1e-12, n, wr, grr);
    for (int dof = kl; dof < kl + 4; ++dof) {
      const double vl = wl[dof - kl], dl = gl[dof - kl];
      const double vr = (dof >= kr && dof < kr + 4) ? wr[dof - kr] : 0.0;
      const double dr = (dof >= kr && dof < kr + 4) ? grr[dof - kr] : 0.0;
      EXPECT_NEAR(vl, vr, 1e-9) << "cell boundary " << c << " dof " << dof;
      EXPECT_NEAR(dl, dr, 1e-9) << "cell boundary " << c << " dof " << dof;
    }
  }
}

TEST(Shape, PointOutsideTheGridIsRejected) {
  GridGeometry<2> g;
  g.cells = {4, 4};
  LinearKernel<2>::StencilT st;
  EXPECT_FALSE(LinearKernel<2>{}(g, Vec<2>(-1.5, 0.5), Vec<2>(0.25, 0.25), Mat<2>::Identity(), st));
  BsplineKernel<2>::StencilT sb;
  EXPECT_FALSE(BsplineKernel<2>{}(g, Vec<2>(4.01, 0.5), Vec<2>(0.25, 0.25), Mat<2>::Identity(), sb));
}

// The kernel's branch-free three-node form equals eq. 3.14 evaluated region by region
// (gimp_1d) for every offset and particle size, including the region boundaries.
TEST(Shape, GimpThreeNodeFormMatchesEquation314) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double L = 0.3;
  double worst_w = 0.0, worst_g = 0.0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double lam = trial < 10 ? 0.5 : 1e-3 + 0.499 * u(rng);
    double e = -0.5 + u(rng);
    if (trial % 7 == 0) e = (trial % 14 == 0) ? lam : -lam;  // on a region boundary
    if (trial % 11 == 0) e = (trial % 22 == 0) ? 0.5 - 1e-15 : -0.5;
    double w[3], g[3];
    gimp_3nodes(e, lam, 1.0 / lam, w, g);
    for (int a = 0; a < 3; ++a) {
      double wr, gr;
      gimp_1d((e - (a - 1)) * L, L, lam * L, wr, gr);  // node n - 1 + a at distance x_p - x_i
      worst_w = std::max(worst_w, std::abs(w[a] - wr));
      worst_g = std::max(worst_g, std::abs(g[a] / L - gr) * L);
    }
  }
  EXPECT_LT(worst_w, 1e-14);
  EXPECT_LT(worst_g, 1e-13);
}

// Packed storage recovers the omitted weight from partition of unity: the unpacked weights
// equal the kernel's own to round-off, for every separable kernel.
template <class K>
void check_packing(const K& kernel, bool bspline) {
  const GridGeometry<2> g = make_grid<2>(bspline);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec<2> x(g.origin[0] + 0.1 + u(rng) * (g.h * g.cells[0] - 0.2),
                   g.origin[1] + 0.1 + u(rng) * (g.h * g.cells[1] - 0.2));
    typename K::Shape sh, back;
    ASSERT_TRUE(kernel.shape(g, x, Vec<2>::Constant(g.h / 4), shear<2>(), sh));
    typename K::Packed packed;
    kernel.store(packed, sh, shear<2>());
    kernel.load(packed, g, x, Vec<2>::Constant(g.h / 4), back);
    ASSERT_EQ(back.base, sh.base);
    for (int d = 0; d < 2; ++d)
      for (int a = 0; a < K::S; ++a) {
        worst = std::max(worst, std::abs(back.w[d][a] - sh.w[d][a]));
        worst = std::max(worst, std::abs(back.g[d][a] - sh.g[d][a]) * g.h);
      }
  }
  EXPECT_LT(worst, 1e-14) << K::name;
}

TEST(Shape, PackedWeightsRoundTrip) {
  check_packing(LinearKernel<2>{}, false);
  check_packing(GimpKernel<2>{}, false);
  check_packing(BsplineKernel<2>{}, true);
}

// The 3D GIMP size (eq. 3.23): det(F)^(-1/3) matches the library's cube root to a few units in
// the last place over the range of volume ratios a run meets and far beyond it, and the
// half-lengths and their inverses formed with one division match lam = l0 J^(1/3) / L and
// 1/lam from std::cbrt and divisions, also where they are clamped and for zero, negative and
// non-finite J.
TEST(Shape, GimpSizeMatchesTheLibraryCubeRoot) {
  double worst = 0.0;
  for (double J = 1e-12; J < 1e12; J *= 1.0007)
    worst = std::max(worst, std::abs(gimp_inverse_cube_root(J) * std::cbrt(J) - 1.0));
  std::printf("largest relative difference of 1/cbrt to std::cbrt: %.2e\n", worst);
  EXPECT_LT(worst, 1e-15);
  const GimpKernel<3> k;
  GridGeometry<3> g;
  g.h = 0.25;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  double worst_lam = 0.0, worst_inv = 0.0;
  for (int n = 0; n < 20000; ++n) {
    Mat<3> F = Mat<3>::Identity();
    for (int i = 0; i < 9; ++i) F(i / 3, i % 3) += u(rng);
    if (n % 5 == 1) F *= 3.0;                                             // beyond the clamp at 1/2
    if (n % 5 == 2) F *= 1e-5;                                            // the lower clamp
    if (n % 97 == 3) F.col(0) = F.col(1);                                 // J = 0
    if (n % 89 == 4) F(0, 0) = std::numeric_limits<double>::quiet_NaN();  // non-finite
    const Vec<3> half0(0.0625 * (1.0 + u(rng)), 0.0625 * (1.0 + u(rng)), 0.0625);
    const auto s = k.size(g, half0, F);
    const double c = std::cbrt(F.determinant());
    for (int d = 0; d < 3; ++d) {
      const double lam = std::clamp(half0[d] * c / g.h, 1e-12, 0.5);
      if (std::isnan(lam)) {
        EXPECT_TRUE(std::isnan(s.lam[d]));
        continue;
      }
      worst_lam = std::max(worst_lam, std::abs(s.lam[d] - lam) / lam);
      worst_inv = std::max(worst_inv, std::abs(s.inv[d] * lam - 1.0));
    }
  }
  std::printf("GIMP size: lam %.2e, 1/lam %.2e from the library's\n", worst_lam, worst_inv);
  EXPECT_LT(worst_lam, 2e-15);  // a few units in the last place
  EXPECT_LT(worst_inv, 2e-15);
}

// GimpKernel<3>::sizes (eight points' sizes in the lanes of vectors, for the move phase) gives
// what size() gives, bit for bit, for every count of points and where size() takes its
// fallback (J = 0, not finite, l0 = 0).
TEST(Shape, GimpSizesInLanesEqualSize) {
  const GimpKernel<3> k;
  GridGeometry<3> g;
  g.h = 0.25;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<Mat<3>> F(4000, Mat<3>::Identity());
  std::vector<Vec<3>> half0(F.size());
  for (std::size_t n = 0; n < F.size(); ++n) {
    for (int i = 0; i < 9; ++i) F[n](i / 3, i % 3) += u(rng);
    if (n % 5 == 1) F[n] *= 3.0;
    if (n % 5 == 2) F[n] *= 1e-5;
    if (n % 97 == 3) F[n].col(0) = F[n].col(1);
    if (n % 89 == 4) F[n](0, 0) = std::numeric_limits<double>::quiet_NaN();
    half0[n] = Vec<3>(0.0625 * (1.0 + u(rng)), 0.0625 * (1.0 + u(rng)), n % 101 == 7 ? 0.0 : 0.0625);
  }
  long compared = 0, differ = 0;
  GimpKernel<3>::Size out[GimpKernel<3>::kSizeLanes];
  for (std::size_t first = 0; first + 8 <= F.size(); first += 8) {
    const int count = 1 + static_cast<int>(first / 8) % 8;  // 1 to 8 points
    k.sizes(g, half0.data() + first, F.data() + first, count, out);
    for (int l = 0; l < count; ++l) {
      const auto s = k.size(g, half0[first + l], F[first + l]);
      for (int d = 0; d < 3; ++d, ++compared)
        differ += std::memcmp(&s.lam[d], &out[l].lam[d], sizeof(double)) != 0 ||
                  std::memcmp(&s.inv[d], &out[l].inv[d], sizeof(double)) != 0;
    }
  }
  EXPECT_GT(compared, 5000);
  EXPECT_EQ(differ, 0);
}

// gather_layers (the walls' share of the lumped mass's loss reads s_i, zero off the walls, on the
// wall layers of a block only) equals the full gather of the field zeroed off those layers, for
// every combination of layers, in 2D and 3D.
template <int D>
void check_gather_layers() {
  const GridGeometry<D> g = make_grid<D>(false);
  const NodeStrides<D> strides(g);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<D>> f(g.node_count());
  for (Vec<D>& v : f)
    for (int d = 0; d < D; ++d) v[d] = u(rng) - 0.5;
  const GimpKernel<D> kernel;
  for (int trial = 0; trial < 200; ++trial) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = g.origin[d] + 0.1 + u(rng) * (g.h * g.cells[d] - 0.2);
    typename GimpKernel<D>::Shape sh;
    ASSERT_TRUE(kernel.shape(g, x, Vec<D>::Constant(g.h / 4), Mat<D>::Identity(), sh));
    std::array<unsigned, D> layers{};
    for (int d = 0; d < D; ++d) layers[d] = static_cast<unsigned>(rng() % 8u);  // any of 3 layers
    std::vector<Vec<D>> zeroed(f.size(), Vec<D>::Zero());
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto ij = g.unflatten(i), b = g.unflatten(sh.base);
      bool on = false;
      for (int d = 0; d < D; ++d) {
        const int k = ij[d] - b[d];
        on = on || (k >= 0 && k < 3 && ((layers[d] >> k) & 1u));
      }
      if (on) zeroed[i] = f[i];
    }
    EXPECT_LT((gather_layers(sh, strides, f.data(), layers) - gather(sh, strides, zeroed.data())).norm(),
              1e-14);
  }
}

TEST(Shape, GatherOnWallLayersIsTheGatherOfTheFieldOnThem) {
  check_gather_layers<2>();
  check_gather_layers<3>();
}
