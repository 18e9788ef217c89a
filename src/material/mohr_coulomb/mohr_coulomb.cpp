// Mohr-Coulomb return mapping in principal stress space (Thesis eq. 5.1-5.4; Clausen,
// Damkilde & Andersen 2006/2007). See mohr_coulomb.hpp for the interface.
//
// Principal space, ordered sigma_1 <= sigma_2 <= sigma_3, tension positive. Every surface is a
// plane f_i = a_i . sigma - k_i with plastic-potential gradient b_i (eq. 5.3):
//   0  f   : the yield plane of eq. 5.1, a = (-(1 - sin phi), 0, 1 + sin phi)/2, k = c cos phi,
//            b = (-(1 - sin psi), 0, 1 + sin psi)/2 (eq. 5.4)
//   1  f_B : eq. 5.1 with sigma_2 as the major stress (the neighbour sector across the
//            compression edge sigma_2 = sigma_3): a = (-(1 - sin phi), 1 + sin phi, 0)/2
//   2  f_C : eq. 5.1 with sigma_2 as the minor stress (across the extension edge
//            sigma_1 = sigma_2): a = (0, -(1 - sin phi), 1 + sin phi)/2
//   3, 4, 5: Rankine tension cut-off sigma_3, sigma_2, sigma_1 <= t (associated: b = a).
// A return onto the intersection of active planes J is sigma = sigma^tr - D sum_{i in J} dl_i b_i
// with f_j(sigma) = 0 for j in J, i.e. the |J| x |J| system sum_i (a_j . D b_i) dl_i = f_j(sigma^tr),
// where D = lambda 1 1^T + 2G I is the elastic stiffness in principal space.
//
// Region selection, Mohr-Coulomb alone (Clausen et al.; closed form, no iteration):
//  1. plane return sigma_p = sigma^tr - dl D b_0; if sigma_p is still ordered it is the answer.
//     (The plane/edge region boundaries are the planes through an edge spanned by the edge
//     direction and D b_0, which is exactly where the ordering of sigma_p flips.)
//  2. sigma_p2 > sigma_p3: return to the compression edge (planes 0, 1); sigma_p1 > sigma_p2:
//     to the extension edge (planes 0, 2). The edge return projects along the plane spanned by
//     the two D b_i onto the edge line; if it lands beyond the apex (sigma_1 > sigma_2 on the
//     compression edge, sigma_2 > sigma_3 on the extension edge) the trial is in the apex region.
//  3. apex: sigma = c cot(phi) (1, 1, 1), d_eps_p = D^-1 (sigma^tr - sigma). Inside the cone of
//     the D b_i this is the non-negative combination of eq. 5.3; outside it (e.g. psi = 0 and a
//     mean trial stress above the apex, where the flow rule admits no return at all) it is the
//     usual non-associated apex treatment of Clausen et al.: the apex is the only admissible point
//     the return can reach, and the plastic strain is whatever closes sigma = sigma^tr - C:d_eps_p.
// For phi = 0 (Tresca) there is no apex and the edges are infinite lines.
//
// With the tension cut-off the surfaces above are combined with the Rankine planes, and the
// candidates (faces, then edges, then vertices) are tried in turn: a candidate is the right one
// when its multipliers are non-negative, the result is admissible (f <= 0, sigma_3 <= t) and still
// ordered (Koiter's conditions; these are Clausen's region boundaries written as sign tests). The
// first that passes to round-off is taken; because the return map is continuous, one accepted
// within round-off of a region boundary is the correct answer to round-off. If none passes
// (round-off in degenerate input, or a non-associated gap as at the apex above) the
// least-violating candidate is used.
#include "material/mohr_coulomb/mohr_coulomb.hpp"

namespace skred {

namespace {

using R = MohrCoulombRegion;

struct Plane {
  Vec3 a;    // gradient of the yield function
  double k;  // f = a . sigma - k
  Vec3 b;    // gradient of the plastic potential
  Vec3 Db;   // D b
  double Db_norm;
};

struct Candidate {
  int n;
  int idx[3];
  R region;
};

// Mohr-Coulomb alone: plane and the two edges (the apex is handled in closed form).
constexpr Candidate kMohrCoulomb[] = {
    {1, {0, 0, 0}, R::Plane},
    {2, {0, 1, 0}, R::CompressionEdge},
    {2, {0, 2, 0}, R::ExtensionEdge},
};

// With the tension cut-off below the apex (the apex is cut away). The corner where the compression
// edge meets the cut-off has four active planes (f, f_B, sigma_3 = t, sigma_2 = t); by
// Caratheodory the return direction lies in the cone of three of them, so each independent
// triple is a candidate.
constexpr Candidate kWithTension[] = {
    {1, {0, 0, 0}, R::Plane},
    {1, {3, 0, 0}, R::Tension},
    {2, {0, 1, 0}, R::CompressionEdge},
    {2, {0, 2, 0}, R::ExtensionEdge},
    {2, {0, 3, 0}, R::PlaneTension},
    {2, {3, 4, 0}, R::TensionEdge},
    {3, {0, 2, 3}, R::ExtensionCorner},
    {3, {0, 1, 3}, R::CompressionCorner},
    {3, {0, 3, 4}, R::CompressionCorner},
    {3, {1, 3, 4}, R::CompressionCorner},
    {3, {0, 1, 4}, R::CompressionCorner},
    {3, {3, 4, 5}, R::TensionApex},
};

inline Vec3 stiffness_times(const ElasticConstants& e, const Vec3& v) {
  return Vec3::Constant(e.lambda * v.sum()) + e.two_g * v;
}

// Solves the candidate's system for the multipliers; false if the planes are dependent.
bool solve_multipliers(const Plane* P, const Candidate& c, const Vec3& st, double (&x)[3]) {
  if (c.n == 1) {
    const Plane& p = P[c.idx[0]];
    const double A = p.a.dot(p.Db);
    if (!(A > 0.0)) return false;
    x[0] = (p.a.dot(st) - p.k) / A;
    return true;
  }
  if (c.n == 2) {
    const Plane &p = P[c.idx[0]], &q = P[c.idx[1]];
    const double a00 = p.a.dot(p.Db), a01 = p.a.dot(q.Db);
    const double a10 = q.a.dot(p.Db), a11 = q.a.dot(q.Db);
    const double det = a00 * a11 - a01 * a10;
    if (!(std::abs(det) > 1e-12 * std::abs(a00 * a11))) return false;
    const double r0 = p.a.dot(st) - p.k, r1 = q.a.dot(st) - q.k;
    x[0] = (a11 * r0 - a01 * r1) / det;
    x[1] = (a00 * r1 - a10 * r0) / det;
    return true;
  }
  Mat3 A;
  Vec3 r;
  for (int j = 0; j < 3; ++j) {
    const Plane& pj = P[c.idx[j]];
    r[j] = pj.a.dot(st) - pj.k;
    for (int i = 0; i < 3; ++i) A(j, i) = pj.a.dot(P[c.idx[i]].Db);
  }
  const double det = A.determinant();
  const double bound = A.row(0).norm() * A.row(1).norm() * A.row(2).norm();  // Hadamard
  if (!(std::abs(det) > 1e-12 * bound)) return false;
  const Vec3 sol = A.inverse() * r;
  x[0] = sol[0];
  x[1] = sol[1];
  x[2] = sol[2];
  return true;
}

// Replaces round-off in the coordinates that the region fixes exactly.
void snap(R region, const MohrCoulombConstants& k, Vec3& s) {
  const double t = k.tension_cutoff;
  switch (region) {
    case R::CompressionEdge: s[1] = s[2] = 0.5 * (s[1] + s[2]); break;
    case R::ExtensionEdge: s[0] = s[1] = 0.5 * (s[0] + s[1]); break;
    case R::Apex: s.setConstant(k.apex); break;
    case R::Tension:
    case R::PlaneTension: s[2] = t; break;
    case R::TensionEdge: s[1] = s[2] = t; break;
    case R::TensionApex: s.setConstant(t); break;
    case R::ExtensionCorner:
    case R::CompressionCorner: {
      // f = 0 with sigma_3 = t: sigma_1 = ((1 + sin phi) t - 2 c cos phi)/(1 - sin phi).
      const double s1 = ((1.0 + k.sin_phi) * t - 2.0 * k.c_cos_phi) / (1.0 - k.sin_phi);
      s[2] = t;
      if (region == R::ExtensionCorner) {
        s[0] = s[1] = s1;
      } else {
        s[0] = s1;
        s[1] = t;
      }
      break;
    }
    default: break;
  }
}

}  // namespace

MohrCoulombRegion mohr_coulomb_return(const ElasticConstants& e, const MohrCoulombConstants& k,
                                      double sin_psi, Vec3& sigma, Vec3& deps_p) {
  const Vec3 st = sigma;
  const bool tension = k.has_tension_cutoff();
  const double t = k.tension_cutoff;
  const double scale =
      k.c_cos_phi + std::max(std::abs(st[0]), std::abs(st[2])) + (tension ? std::abs(t) : 0.0);
  const double tol = kYieldRelTol * scale;
  deps_p.setZero();
  if (mohr_coulomb_yield(k, st) <= tol && (!tension || st[2] - t <= tol)) return R::Elastic;

  // The planes (see the file comment); the Rankine ones only with the cut-off.
  const double sp = k.sin_phi, sq = sin_psi;
  Plane P[6];
  P[0].a = Vec3(-(1.0 - sp), 0.0, 1.0 + sp) * 0.5;
  P[0].b = Vec3(-(1.0 - sq), 0.0, 1.0 + sq) * 0.5;
  P[0].k = k.c_cos_phi;
  P[0].Db = stiffness_times(e, P[0].b);

  if (!tension) {
    // 1. Plane (the common case: nothing else is needed).
    const double dl = (P[0].a.dot(st) - P[0].k) / P[0].a.dot(P[0].Db);
    const Vec3 s_p = st - dl * P[0].Db;
    const bool c_edge = s_p[1] > s_p[2], e_edge = s_p[0] > s_p[1];
    if (!c_edge && !e_edge) {
      deps_p = dl * P[0].b;
      sigma = s_p;
      return R::Plane;
    }
  }
  P[1].a = Vec3(-(1.0 - sp), 1.0 + sp, 0.0) * 0.5;
  P[1].b = Vec3(-(1.0 - sq), 1.0 + sq, 0.0) * 0.5;
  P[2].a = Vec3(0.0, -(1.0 - sp), 1.0 + sp) * 0.5;
  P[2].b = Vec3(0.0, -(1.0 - sq), 1.0 + sq) * 0.5;
  P[1].k = P[2].k = k.c_cos_phi;
  const int nplanes = tension ? 6 : 3;
  for (int i = 3; i < nplanes; ++i) {
    P[i].a = Vec3::Unit(5 - i);  // 3 -> sigma_3, 4 -> sigma_2, 5 -> sigma_1
    P[i].b = P[i].a;
    P[i].k = t;
  }
  for (int i = 0; i < nplanes; ++i) {
    P[i].Db = stiffness_times(e, P[i].b);
    P[i].Db_norm = P[i].Db.norm();
  }

  if (!tension) {
    const double dl = (P[0].a.dot(st) - P[0].k) / P[0].a.dot(P[0].Db);
    const Vec3 s_p = st - dl * P[0].Db;
    const bool c_edge = s_p[1] > s_p[2], e_edge = s_p[0] > s_p[1];
    // 2. The edge(s) the plane return crossed; valid if it lands on the apex side.
    for (int pass = 0; pass < 2; ++pass) {
      const bool comp = pass == 0;
      if (comp ? !c_edge : !e_edge) continue;
      const Candidate& c = kMohrCoulomb[comp ? 1 : 2];
      double x[3];
      if (!solve_multipliers(P, c, st, x)) continue;
      const Vec3 ep = x[0] * P[0].b + x[1] * P[c.idx[1]].b;
      Vec3 s = st - stiffness_times(e, ep);
      if (!(k.sin_phi > 0.0) || (comp ? s[0] <= s[1] : s[1] <= s[2])) {
        snap(c.region, k, s);
        sigma = s;
        deps_p = ep;
        return c.region;
      }
    }
    // 3. Apex (phi > 0): d_eps_p = D^-1 (sigma^tr - apex).
    if (k.sin_phi > 0.0) {
      sigma.setConstant(k.apex);
      const Vec3 ds = st - sigma;
      deps_p = (ds - Vec3::Constant(e.lambda / (3.0 * e.lambda + e.two_g) * ds.sum())) / e.two_g;
      return R::Apex;
    }
    // phi = 0 and neither edge valid: cannot happen for c >= 0; fall through to the search.
  }

  const Candidate* list = tension ? kWithTension : kMohrCoulomb;
  const int count = tension ? int(std::size(kWithTension)) : 3;

  double best = std::numeric_limits<double>::infinity();
  R best_region = R::Plane;
  Vec3 best_s = st, best_ep = Vec3::Zero();
  for (int ci = 0; ci < count; ++ci) {
    const Candidate& c = list[ci];
    double x[3] = {0.0, 0.0, 0.0};
    if (!solve_multipliers(P, c, st, x)) continue;
    Vec3 ep = Vec3::Zero();
    double viol = -std::numeric_limits<double>::infinity();
    for (int m = 0; m < c.n; ++m) {
      ep += x[m] * P[c.idx[m]].b;
      viol = std::max(viol, -x[m] * P[c.idx[m]].Db_norm);  // dl_i >= 0
    }
    const Vec3 s = st - stiffness_times(e, ep);
    viol = std::max({viol, mohr_coulomb_yield(k, s), s[0] - s[1], s[1] - s[2]});
    if (tension) viol = std::max(viol, s[2] - t);
    if (viol < best) {
      best = viol;
      best_region = c.region;
      best_s = s;
      best_ep = ep;
      if (viol <= tol) break;
    }
  }
  snap(best_region, k, best_s);
  sigma = best_s;
  deps_p = best_ep;
  return best_region;
}

namespace detail {

Sym3 mohr_coulomb_plastic(const ElasticConstants& e, const MohrCoulombConstants& k, Sym3& stress,
                          const Sym3& trial, PointState& state, MohrCoulombRegion* region) {
  const Principal pd = principal_decomposition(trial);
  // Dilation cut-off (Paper III §C.3.2): psi = 0 once e = (1 + e0) exp(eps_v) - 1 >= e_max,
  // evaluated with the updated volume strain.
  const double sin_psi = state.volume_strain >= k.max_volume_strain ? 0.0 : k.sin_psi;
  Vec3 s = pd.values, ep;
  const R r = mohr_coulomb_return(e, k, sin_psi, s, ep);
  if (region) *region = r;
  if (r == R::Elastic) {  // admissible within the tolerance after all
    stress = trial;
    state.yielding = 0;
    return Sym3::Zero();
  }
  stress = from_principal(s, pd.vectors);
  record_plastic_strain(ep, state);
  return from_principal(ep, pd.vectors);
}

}  // namespace detail

}  // namespace skred
