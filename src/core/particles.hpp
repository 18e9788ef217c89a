// Material points stored as structure-of-arrays (one std::vector per field). Every per-point
// field is declared once, in fields(); the lifecycle of the points (reserve, add, erase,
// duplicate, reorder, sort by cell, serialise) is written once over that list, so a field
// added to the list is carried by all of them.
#pragma once
#include <omp.h>

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "core/grid.hpp"
#include "core/huge_pages.hpp"
#include "core/point_state.hpp"
#include "core/types.hpp"

namespace skred {

// Material and body ids are stored in 16 bits: a scenario has fewer of each (the scenario
// builder checks).
inline constexpr int kMaxIds = 32767;

// A run sorts the points by cell (Particles::sort_by_cell) before every step whose number is
// a multiple of this, the first step included (docs/method.md, "Point order").
inline constexpr long kSortEvery = 100;

// One per-point field: its name (in checkpoints), the array, and the value a new point gets.
// An optional field may be empty, meaning every point has the initial value (it is then left
// empty by every operation).
template <class P, class T>
struct ParticleField {
  using value_type = T;
  const char* name;
  std::vector<T> P::*member;
  T (*initial)();
  bool optional = false;
};

template <int D>
struct Particles {
  // Thesis §2.2: position, velocity, mass and initial volume of each material point.
  std::vector<Vec<D>> x;               // current position x_p
  std::vector<Vec<D>> x_ref;           // position at the start of the stage (displacement = x - x_ref)
  std::vector<Vec<D>> v;               // velocity v_p
  std::vector<double> mass;            // m_p
  std::vector<double> volume0;         // V_p^0 (current volume V_p = det(F_p) V_p^0)
  std::vector<Vec<D>> half0;           // voxel half-lengths l_p^0 in the reference configuration
  std::vector<Mat<D>> F;               // deformation gradient F_p (Thesis eq. 3.1-3.5)
  std::vector<PointStress<D>> stress;  // Cauchy stress incl. the out-of-plane component (Voigt)
  std::vector<std::int16_t> material;  // index into the scenario's material table
  std::vector<std::int16_t> body;      // index into the scenario's body table (see kMaxBodies)
  std::vector<PointState> state;       // constitutive state (plastic strain, yield flag)
  // Elastic part of F (F = Fe Fp, Post eq. 67-74), identity at the reference state, and the
  // stress of that reference state (sigma_initial of Post eq. 77). Both are post-processing only
  // (no law reads them): Fe is stored once track_elastic_F() is called (a run whose frames hold
  // Fe, Fp or stress_from_Fe), the reference stress once an initial stress is set while Fe is
  // tracked (set_reference_stress); empty, the reference stress is zero.
  std::vector<Mat<D>> Fe;
  std::vector<PointStress<D>> stress_ref;
  // Plastic shear strain at the start of the stage (like x_ref; set by the StageTracker),
  // for the plastified volume of a stage.
  std::vector<double> plastic_ref;
  // Material-point splitting (Thesis §3.4), present once enable_splitting() was called:
  // the gauge G with F_split = F G (both follow eq. 3.2 with the same increment, so G only
  // changes when a split resets a mode) and the number of splits behind each point.
  std::vector<Mat<D>> split_gauge;
  std::vector<std::int16_t> splits;
  // Affine velocity C_p of the APIC transfer (Jiang et al. 2015), carried to the nodes by the
  // next map; stored only while that transfer is used (empty: zero).
  std::vector<Mat<D>> affine;
  // Positions at the start of the rest test's window (Stage::rest_measure "displacement", set by
  // the StageTracker); stored only while a stage uses it.
  std::vector<Vec<D>> x_rest;
  // 1 for a point that moved past the hazard maps' threshold in an earlier stage of the run
  // (run/hazard_maps.hpp: the run's deposit over several stages); stored once a 3D run with
  // maps has finished a stage.
  std::vector<std::uint8_t> moved;

  // The implicit integrator's (src/implicit): the points' acceleration a_p of Newmark's rule
  // (Acosta eq. 8-10, 41), stored only while a dynamic implicit stage runs; and in axisymmetric
  // geometry the hoop stretch F_theta_theta = r / r_0 (App. A1), stored only there. Empty: zero
  // and one.
  std::vector<Vec<D>> acceleration;
  std::vector<double> hoop;
  // The field list: every per-point array, once, with the value of a new point.
  static constexpr auto fields() {
    using Pt = Particles;
    return std::tuple{
        ParticleField<Pt, Vec<D>>{"x", &Pt::x, +[] { return Vec<D>(Vec<D>::Zero()); }},
        ParticleField<Pt, Vec<D>>{"x_ref", &Pt::x_ref, +[] { return Vec<D>(Vec<D>::Zero()); }},
        ParticleField<Pt, Vec<D>>{"v", &Pt::v, +[] { return Vec<D>(Vec<D>::Zero()); }},
        ParticleField<Pt, double>{"mass", &Pt::mass, +[] { return 0.0; }},
        ParticleField<Pt, double>{"volume0", &Pt::volume0, +[] { return 0.0; }},
        ParticleField<Pt, Vec<D>>{"half0", &Pt::half0, +[] { return Vec<D>(Vec<D>::Zero()); }},
        ParticleField<Pt, Mat<D>>{"F", &Pt::F, +[] { return Mat<D>(Mat<D>::Identity()); }},
        ParticleField<Pt, PointStress<D>>{"stress", &Pt::stress,
                                          +[] { return PointStress<D>(PointStress<D>::Zero()); }},
        ParticleField<Pt, std::int16_t>{"material", &Pt::material, +[] { return std::int16_t{0}; }},
        ParticleField<Pt, std::int16_t>{"body", &Pt::body, +[] { return std::int16_t{0}; }},
        ParticleField<Pt, PointState>{"state", &Pt::state, +[] { return PointState{}; }},
        ParticleField<Pt, Mat<D>>{"Fe", &Pt::Fe, +[] { return Mat<D>(Mat<D>::Identity()); }, true},
        ParticleField<Pt, PointStress<D>>{"stress_ref", &Pt::stress_ref,
                                          +[] { return PointStress<D>(PointStress<D>::Zero()); }, true},
        ParticleField<Pt, double>{"plastic_ref", &Pt::plastic_ref, +[] { return 0.0; }},
        ParticleField<Pt, Mat<D>>{"split_gauge", &Pt::split_gauge, +[] { return Mat<D>(Mat<D>::Identity()); },
                                  true},
        ParticleField<Pt, std::int16_t>{"splits", &Pt::splits, +[] { return std::int16_t{0}; }, true},
        ParticleField<Pt, Mat<D>>{"affine", &Pt::affine, +[] { return Mat<D>(Mat<D>::Zero()); }, true},
        ParticleField<Pt, Vec<D>>{"x_rest", &Pt::x_rest, +[] { return Vec<D>(Vec<D>::Zero()); }, true},
        ParticleField<Pt, std::uint8_t>{"moved", &Pt::moved, +[] { return std::uint8_t{0}; }, true},
        ParticleField<Pt, Vec<D>>{"acceleration", &Pt::acceleration, +[] { return Vec<D>(Vec<D>::Zero()); },
                                  true},
        ParticleField<Pt, double>{"hoop", &Pt::hoop, +[] { return 1.0; }, true},
    };
  }

  // fn(field, array) for every field of the list (the arrays of optional empty fields too).
  template <class Fn>
  void for_each_field(Fn&& fn) {
    std::apply([&](const auto&... f) { (fn(f, this->*f.member), ...); }, fields());
  }
  template <class Fn>
  void for_each_field(Fn&& fn) const {
    std::apply([&](const auto&... f) { (fn(f, this->*f.member), ...); }, fields());
  }
  // The same for the fields that hold one entry per point (every field but empty optional ones).
  template <class Fn>
  void for_each_present_field(Fn&& fn) {
    for_each_field([&](const auto& f, auto& a) {
      if (!(f.optional && a.empty())) fn(f, a);
    });
  }

  std::size_t size() const { return x.size(); }

  // Room for n points, on huge pages where the arrays are large (see huge_pages.hpp).
  void reserve(std::size_t n) {
    for_each_present_field([&](const auto&, auto& a) { reserve_huge(a, n); });
  }

  // Gives back the capacity beyond the points held (after erase() of most of them), the arrays
  // moved to buffers of their size (asking for huge pages as reserve() does).
  void shrink() {
    for_each_present_field([&](const auto&, auto& a) {
      std::decay_t<decltype(a)> b;
      reserve_huge(b, a.size());
      b.assign(a.begin(), a.end());
      a.swap(b);
    });
  }

  // Appends one point with every field at its initial value; returns its index.
  std::size_t add_default() {
    for_each_present_field([&](const auto& f, auto& a) { a.push_back(f.initial()); });
    return size() - 1;
  }

  // Appends one undeformed, stress-free material point.
  void add(const Vec<D>& pos, const Vec<D>& vel, double m, double vol, const Vec<D>& half, int mat, int bod) {
    assert(mat >= 0 && mat < kMaxIds && bod >= 0 && bod < kMaxIds);
    const std::size_t p = add_default();
    x[p] = pos;
    x_ref[p] = pos;
    v[p] = vel;
    mass[p] = m;
    volume0[p] = vol;
    half0[p] = half;
    material[p] = static_cast<std::int16_t>(mat);
    body[p] = static_cast<std::int16_t>(bod);
  }

  // Appends a copy of point p (every field) and returns its index: the start of a split, or
  // of any copy with changes.
  std::size_t duplicate(std::size_t p) {
    assert(p < size());
    for_each_present_field([&](const auto&, auto& a) {
      const auto value = a[p];  // push_back may reallocate
      a.push_back(value);
    });
    return size() - 1;
  }

  // Splits point p in two along reference axis `axis`: each half keeps p's velocity, stress,
  // F and state, with half its mass, volume and voxel length along the axis, centred at
  // x_p -+ F_p l_p^0 e_axis / 2 (the centres of the two halves of the deformed voxel, Thesis
  // eq. 3.6-3.12). Mass and momentum are conserved exactly. Returns the new point's index.
  std::size_t split(std::size_t p, int axis) {
    const std::size_t q = duplicate(p);
    half0[p][axis] *= 0.5;
    half0[q][axis] = half0[p][axis];
    const Vec<D> shift = F[p].col(axis) * half0[p][axis];
    const Vec<D> shift_ref = Vec<D>::Unit(axis) * half0[p][axis];
    x[p] -= shift;
    x[q] += shift;
    x_ref[p] -= shift_ref;
    x_ref[q] += shift_ref;
    if (!x_rest.empty()) {  // a split moves no material: the halves' window starts where they are
      x_rest[p] -= shift;
      x_rest[q] += shift;
    }
    mass[p] *= 0.5;
    mass[q] = mass[p];
    volume0[p] *= 0.5;
    volume0[q] = volume0[p];
    return q;
  }

  // Appends the points of `o` after these (an optional field that one of them lacks takes its
  // initial value there). Joins the pieces of a checkpoint written by several processes.
  void append(const Particles& o) {
    const std::size_t n = size(), m = o.size();
    for_each_field([&](const auto& f, auto& a) {
      const auto& b = o.*f.member;
      if (f.optional && a.empty() && b.empty()) return;
      if (a.size() != n) a.assign(n, f.initial());
      if (b.size() == m)
        a.insert(a.end(), b.begin(), b.end());
      else
        a.insert(a.end(), m, f.initial());
    });
  }

  // Removes the points whose keep[p] is 0, keeping the order of the others (stable
  // compaction; no allocation). keep has one entry per point.
  void erase(const std::vector<std::uint8_t>& keep) {
    assert(keep.size() == size());
    for_each_present_field([&](const auto&, auto& a) {
      std::size_t j = 0;
      for (std::size_t i = 0; i < a.size(); ++i)
        if (keep[i]) a[j++] = a[i];
      a.resize(j);
    });
  }
  // Removes the listed points (any order, repeats allowed).
  void erase_points(const std::vector<std::size_t>& points) {
    std::vector<std::uint8_t> keep(size(), 1);
    for (std::size_t p : points) keep.at(p) = 0;
    erase(keep);
  }

  // Reorders the points: the point at new index i is the one at old index order[i]; order is
  // a permutation of 0..size()-1. In place, one cycle at a time: the cycles are found once,
  // and the fields, shared among `threads` OpenMP threads, follow them (scratch kept for reuse).
  void reorder(const std::vector<std::uint32_t>& order, int threads = 1) {
    assert(order.size() == size());
    const std::size_t n = size();
    visited_.assign(n, 0);
    cycle_starts_.clear();  // the first index of every cycle of two or more points
    for (std::size_t start = 0; start < n; ++start) {
      if (visited_[start] || order[start] == start) continue;
      cycle_starts_.push_back(static_cast<std::uint32_t>(start));
      for (std::size_t i = start; !visited_[i]; i = order[i]) visited_[i] = 1;
    }
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
      const int t = omp_get_thread_num(), nt = omp_get_num_threads();
      int field = 0;
      for_each_present_field([&](const auto&, auto& a) {
        if (field++ % nt != t) return;
        for (const std::uint32_t start : cycle_starts_) {
          auto carried = a[start];
          std::size_t i = start;
          for (std::size_t from = order[i]; from != start; from = order[i]) {
            a[i] = a[from];
            i = from;
          }
          a[i] = carried;
        }
      });
    }
  }

  // Sorts the points by the grid cell that holds them (stable; key = flat cell index with axis
  // 0 fastest, like the grid's node layout), so that points of a cell, which scatter to the
  // same nodes, are neighbours in memory. With `nearest_node`, the key is the node nearest the
  // point instead (the cell of the grid shifted by half a cell): GIMP's block of 3^D nodes
  // starts one node before it, so the points of one key scatter to the very same nodes.
  // Counting sort over the keys; the scratch arrays are kept, so a sort allocates only when the
  // number of points or cells grows. Returns false (and changes nothing) when the points were
  // in order already.
  bool sort_by_cell(const GridGeometry<D>& grid, bool nearest_node = false, int threads = 1) {
    const std::size_t n = size();
    const int extra = nearest_node ? 1 : 0;  // keys per axis: cells, or nodes
    const double shift = nearest_node ? 0.5 : 0.0;
    std::size_t cells = 1;
    for (int d = 0; d < D; ++d) cells *= static_cast<std::size_t>(grid.cells[d] + extra);
    sort_key_.resize(n);
    bool sorted = true;
    for (std::size_t p = 0; p < n; ++p) {
      std::size_t key = 0, stride = 1;
      for (int d = 0; d < D; ++d) {
        const int last = grid.cells[d] + extra - 1;
        const double r = std::floor((x[p][d] - grid.origin[d]) / grid.h + shift);
        const int c = r < 0.0 ? 0 : r > last ? last : static_cast<int>(r);
        key += static_cast<std::size_t>(c) * stride;
        stride *= static_cast<std::size_t>(last + 1);
      }
      sort_key_[p] = static_cast<std::uint32_t>(key);
      if (p > 0 && key < sort_key_[p - 1]) sorted = false;
    }
    if (sorted) return false;
    sort_count_.assign(cells + 1, 0);
    for (std::size_t p = 0; p < n; ++p) ++sort_count_[sort_key_[p] + 1];
    for (std::size_t c = 0; c < cells; ++c) sort_count_[c + 1] += sort_count_[c];
    sort_order_.resize(n);
    for (std::size_t p = 0; p < n; ++p)
      sort_order_[sort_count_[sort_key_[p]]++] = static_cast<std::uint32_t>(p);
    reorder(sort_order_, threads);
    return true;
  }

  // Binary image of every field, in list order: name, entry size, entry count, raw entries
  // (host byte order). deserialise() reads it back into these particles, replacing them, and
  // throws std::runtime_error when the image does not match the field list.
  void serialise(std::ostream& os) const {
    for_each_field([&](const auto& f, const auto& a) {
      using T = typename std::decay_t<decltype(f)>::value_type;
      const std::string name = f.name;
      const std::uint64_t head[3] = {name.size(), sizeof(T), a.size()};
      os.write(reinterpret_cast<const char*>(head), sizeof head);
      os.write(name.data(), static_cast<std::streamsize>(name.size()));
      os.write(reinterpret_cast<const char*>(a.data()), static_cast<std::streamsize>(a.size() * sizeof(T)));
    });
  }
  void deserialise(std::istream& is) {
    std::size_t n = 0;
    bool first = true;
    for_each_field([&](const auto& f, auto& a) {
      using T = typename std::decay_t<decltype(f)>::value_type;
      std::uint64_t head[3] = {};
      is.read(reinterpret_cast<char*>(head), sizeof head);
      std::string name(is ? head[0] : 0, '\0');
      if (is && head[0] < 64) is.read(name.data(), static_cast<std::streamsize>(name.size()));
      if (!is || name != f.name || head[1] != sizeof(T))
        throw std::runtime_error(std::string("particle field '") + f.name + "' missing or of another type");
      if (first) n = head[2];
      first = false;
      if (head[2] != n && !(f.optional && head[2] == 0))
        throw std::runtime_error(std::string("particle field '") + f.name +
                                 "' has the wrong number of points");
      a.resize(head[2]);
      is.read(reinterpret_cast<char*>(a.data()), static_cast<std::streamsize>(a.size() * sizeof(T)));
      if (!is) throw std::runtime_error(std::string("particle field '") + f.name + "' is truncated");
    });
  }

  // The stress of Fe's reference state (Post eq. 77): zero unless an initial stress was set.
  PointStress<D> reference_stress(std::size_t p) const {
    return stress_ref.empty() ? PointStress<D>::Zero() : stress_ref[p];
  }
  // Makes the current stresses the reference state of Fe (after an initial stress is set), if
  // Fe is tracked.
  void set_reference_stress() {
    if (!Fe.empty()) stress_ref = stress;
  }
  // Starts tracking Fe for every point, from Fe = I now (the reference state of Post eq. 77).
  void track_elastic_F() {
    if (Fe.empty()) Fe.assign(size(), Mat<D>::Identity());
  }
  // Starts tracking F_split = F G for every point, from F_split = I now (G = F^-1).
  void enable_splitting() {
    if (!split_gauge.empty()) return;
    split_gauge.resize(size());
    for (std::size_t p = 0; p < size(); ++p) split_gauge[p] = F[p].inverse();
    splits.assign(size(), 0);
  }

  // Current volume V_p = det(F_p) V_p^0 (axisymmetric: per radian, times the hoop stretch).
  double volume(std::size_t p) const {
    return F[p].determinant() * volume0[p] * (hoop.empty() ? 1.0 : hoop[p]);
  }

 private:
  // Scratch of reorder() and sort_by_cell(), kept between calls (not per-point fields).
  std::vector<std::uint8_t> visited_;
  std::vector<std::uint32_t> sort_key_, sort_order_, cycle_starts_;
  std::vector<std::size_t> sort_count_;
};

}  // namespace skred
