// The transfer layer (src/transfer) on its own and the solver's per-body grid fields
// (Paper III §C.2.7), checked against conservation laws and the kernels' exact
// reproduction of linear fields (Thesis eq. 2.46-2.47: partition of unity and its gradient).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "support.hpp"
#include "transfer/transfers.hpp"

using namespace skred;
using namespace skred::test;

namespace {

// Two discs of the R3 set-up as bodies 0 and 1, touching nodes of both in between.
Particles<2> two_bodies() {
  const Material m = elastic(1000.0, 1000.0, 0.3);
  Particles<2> P;
  fill_disc(P, m, 0.05, 2, Vec<2>(0.35, 0.35), 0.2, 1.0, Vec<2>(0.1, 0.05), 0);
  fill_disc(P, m, 0.05, 2, Vec<2>(0.65, 0.62), 0.2, 1.0, Vec<2>(-0.1, -0.02), 1);
  for (std::size_t p = 0; p < P.size(); ++p)  // a rotation, so that momenta differ per node
    P.v[p] += 0.3 * Vec<2>(-(P.x[p][1] - 0.5), P.x[p][0] - 0.5);
  return P;
}

template <class Fn>
void for_each_interpolation(Fn&& fn) {
  for (Interpolation i :
       {Interpolation::Linear, Interpolation::Gimp, Interpolation::Bspline, Interpolation::GimpQuadrature})
    fn(i);
}

}  // namespace

// Each body maps its own m_i^b and p_i^b beside the centre-of-mass fields; at every node the
// bodies' fields add up to the centre-of-mass field, and their totals are the bodies'
// particle mass and momentum. Checked as a step starts and again after 20 steps of the
// averaged scheme (the bodies overlap nodes between them throughout).
TEST(BodyFields, PerBodyFieldsSumToTheCentreOfMassField) {
  for_each_interpolation([](Interpolation interp) {
    Particles<2> P = two_bodies();
    SolverSettings<2> st;
    st.interpolation = interp;
    st.dt = 0.001;
    st.body_fields = true;
    ExplicitSolver<2> solver(grid2(0.05, 20, 20), P, {elastic(1000.0, 1000.0, 0.3)}, st, 2);
    for (int round = 0; round < 2; ++round) {
      ASSERT_TRUE(solver.map_grid().ok);
      const auto& F = solver.fields();
      const auto& B = solver.body_fields();
      ASSERT_EQ(B.size(), 2u);
      double worst_m = 0.0, worst_p = 0.0, scale_m = 0.0, scale_p = 0.0;
      long shared = 0;
      double body_mass[2] = {0, 0};
      for (std::size_t i = 0; i < F.size(); ++i) {
        worst_m = std::max(worst_m, std::abs(B[0].mass[i] + B[1].mass[i] - F.mass[i]));
        worst_p = std::max(worst_p, (B[0].momentum[i] + B[1].momentum[i] - F.momentum[i]).norm());
        scale_m = std::max(scale_m, F.mass[i]);
        scale_p = std::max(scale_p, F.momentum[i].norm());
        shared += B[0].mass[i] > 0.0 && B[1].mass[i] > 0.0;
        body_mass[0] += B[0].mass[i];
        body_mass[1] += B[1].mass[i];
      }
      double particle_mass[2] = {0, 0};
      for (std::size_t p = 0; p < P.size(); ++p) particle_mass[P.body[p]] += P.mass[p];
      EXPECT_GT(shared, 0) << to_string(interp) << ": the bodies share no node";
      EXPECT_LE(worst_m, 1e-13 * scale_m) << to_string(interp);
      EXPECT_LE(worst_p, 1e-13 * scale_p) << to_string(interp);
      for (int b = 0; b < 2; ++b)
        EXPECT_NEAR(body_mass[b], particle_mass[b], 1e-12 * particle_mass[b]) << to_string(interp);
      for (int s = 0; s < 20; ++s) ASSERT_TRUE(solver.step().ok);
      solver.particles_changed();
    }
  });
}

// The whole-array maps: mass and momentum are conserved by p2g (partition of unity), the
// internal forces sum to zero (sum_i grad N_ip = 0), and g2p of a linear nodal velocity field
// gives back the field and its gradient at every point (linear completeness of every kernel).
TEST(Transfers, MapsConserveAndReproduceLinearFields) {
  for_each_interpolation([](Interpolation interp) {
    Particles<2> P = two_bodies();
    for (std::size_t p = 0; p < P.size(); ++p)
      P.stress[p] << -100.0 * P.x[p][1], -50.0, -30.0, 20.0 * P.x[p][0];
    GridGeometry<2> g = grid2(0.05, 20, 20);
    g.bspline_dofs = interp == Interpolation::Bspline;
    Transfer<2> T(g, 2);
    const std::size_t n = g.node_count();
    GridArray<double> m(n);
    GridArray<Vec<2>> mom(n), f(n), v(n);
    with_kernel<2>(interp, 2, [&](const auto& kernel) {
      ASSERT_EQ(p2g_mass_momentum(T, kernel, P, m.data(), mom.data()), -1);
      double mg = 0.0, mp = 0.0;
      Vec<2> pg = Vec<2>::Zero(), pp = Vec<2>::Zero();
      for (std::size_t i = 0; i < n; ++i) mg += m[i], pg += mom[i];
      for (std::size_t p = 0; p < P.size(); ++p) mp += P.mass[p], pp += P.mass[p] * P.v[p];
      EXPECT_NEAR(mg, mp, 1e-12 * mp) << to_string(interp);
      EXPECT_LE((pg - pp).norm(), 1e-12 * pp.norm()) << to_string(interp);

      p2g_internal_force(T, kernel, P, f.data());
      Vec<2> fsum = Vec<2>::Zero();
      double fscale = 0.0;
      for (std::size_t i = 0; i < n; ++i) fsum += f[i], fscale = std::max(fscale, f[i].norm());
      EXPECT_GT(fscale, 0.0);
      EXPECT_LE(fsum.norm(), 1e-11 * fscale) << to_string(interp);

      Mat<2> A;
      A << 0.3, -0.7, 1.1, 0.2;
      const Vec<2> b(0.5, -0.25);
      for (std::size_t i = 0; i < n; ++i) v[i] = A * g.node_position(i) + b;
      std::vector<Vec<2>> vp(P.size());
      std::vector<Mat<2>> lp(P.size());
      g2p_velocity(T, kernel, P, v.data(), vp.data());
      g2p_velocity_gradient(T, kernel, P, v.data(), lp.data());
      double ev = 0.0, el = 0.0;
      for (std::size_t p = 0; p < P.size(); ++p) {
        ev = std::max(ev, (vp[p] - (A * P.x[p] + b)).norm());
        el = std::max(el, (lp[p] - A).norm());
      }
      EXPECT_LE(ev, 1e-12) << to_string(interp);
      EXPECT_LE(el, 1e-11) << to_string(interp);
    });
  });
}

// A thread's scatter buffer holds pages only for the layers of nodes its points span now, not
// for the region they swept (issue 10: buffers must not grow as threads x grid). Thread 1's
// "points" write to 4 layers that move one layer per step along a 3D grid of 400 layers (6.8 MB
// of buffer); the grid receives every write, and the buffer keeps at most the release slack
// (1 MiB of the vector array, 1/3 of that of the mass array) beyond the 4 layers. Released pages
// read as zero when written again.
TEST(Transfers, ScatterBufferHoldsOnlyThePagesOfItsPointsLayers) {
  GridGeometry<3> g;
  g.h = 1.0;
  g.cells = {20, 20, 400};
  const std::size_t layer = g.stride(2), nodes = g.node_count();
  GridArray<double> mass(nodes);
  GridArray<Vec<3>> mom(nodes);
  ScatterBuffers<3> S(nodes, 2);
  NodeBox<3> box;
  for (int d = 0; d < 3; ++d) box.lo[d] = 0, box.hi[d] = g.nodes(d) - 1;
  const auto step = [&](int k) {  // 4 layers from layer k, 1 per node
    double* m = S.mass_target(1, mass.data());
    Vec<3>* p = S.vec_target(1, mom.data());
    for (std::size_t i = k * layer; i < (k + kMaxStencil) * layer; ++i) {
      m[i] += 1.0;
      p[i] += Vec<3>(1.0, 2.0, 3.0);
    }
    BaseSpan span;
    span.add(k * layer);
    S.touched(1, span);
    S.reduce(g, box, 1, mass.data(), mom.data());
  };
  const int steps = g.nodes(2) - kMaxStencil + 1;
  for (int k = 0; k < steps; ++k) step(k);
  const std::size_t held = S.resident_bytes(1), swept = nodes * (sizeof(double) + sizeof(Vec<3>));
  std::printf("scatter buffer after the sweep: %zu bytes resident of %zu swept\n", held, swept);
  EXPECT_LE(held, (std::size_t{1} << 20) * 4 / 3 + 2 * kMaxStencil * layer * 32 + 4 * 4096);
  EXPECT_GT(held, 0u);
  step(0);  // back to the released start of the grid
  double total = 0.0;
  Vec<3> momentum = Vec<3>::Zero();
  for (std::size_t i = 0; i < nodes; ++i) {
    total += mass[i];
    momentum += mom[i];
  }
  const double writes = static_cast<double>((steps + 1) * kMaxStencil * layer);
  EXPECT_EQ(total, writes);
  EXPECT_EQ(momentum, Vec<3>(1.0, 2.0, 3.0) * writes);
  EXPECT_EQ(mass[0], 2.0);  // written twice, the second time into a released page
}

// A grid array is untouched zero pages however the heap stands: after a process of a distributed
// run has freed the others' points, the heap holds large free chunks, and calloc would hand one
// out zeroed by writing it (each process's whole grid resident). 16 MiB of heap in chunks under
// the mmap threshold, freed, then a 8 MiB grid array: none of its pages resident, all read zero.
// (A mapped 12 MiB array freed first raises glibc's threshold, as the set-up's arrays do.)
TEST(Transfers, GridArrayTouchesNoPageWhereTheHeapHasFreeChunks) {
  { std::vector<char> big(12 << 20, 1); }
  std::vector<char*> chunks(256);
  for (char*& c : chunks) {  // (64 KiB each: from the heap, not mapped)
    c = static_cast<char*>(std::malloc(64 << 10));
    std::memset(c, 1, 64 << 10);
  }
  for (std::size_t k = 1; k + 1 < chunks.size(); ++k) std::free(chunks[k]);  // (a free run in the middle)
  GridArray<double> a(std::size_t{1} << 20);
  EXPECT_EQ(resident_bytes(a.data(), a.size() * sizeof(double)), 0u);
  double sum = 0.0;
  for (double v : a) sum += std::abs(v);
  EXPECT_EQ(sum, 0.0);
  a[12345] = 1.0;  // a write makes its page resident
  EXPECT_GT(resident_bytes(a.data(), a.size() * sizeof(double)), 0u);
  std::free(chunks.front());
  std::free(chunks.back());
}
