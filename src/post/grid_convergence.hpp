// How far a result is from its converged value, from the same scenario on three grids:
// Richardson's extrapolation and Roache's grid convergence index (GCI), as the procedure of
// Celik, Ghia, Roache, Freitas, Coleman & Raad (2008), "Procedure for estimation and reporting
// of uncertainty due to discretization in CFD applications", J. Fluids Eng. 130, 078001, sets it
// out (its steps 1-5; ASME V&V 20-2009 §5). `skred refine` applies it to the runout and the
// released energy of the last three cell sizes (docs/method.md, "Richardson's extrapolation").
#pragma once

namespace skred {

// What the three values do as the cell shrinks, by R = ε21 / ε32 with ε21 = φ2 − φ1 and
// ε32 = φ3 − φ2 (φ1 on the finest grid):
enum class ConvergenceKind {
  monotone,     // 0 < R < 1: each change smaller than the one before, in the same direction
  oscillatory,  // −1 < R < 0: the changes alternate in sign and shrink (Celik: extrapolate with care)
  diverging,    // |R| ≥ 1: the last change is as large as the one before or larger: not yet in
                // the asymptotic range, so nothing is extrapolated
  unchanged,    // ε21 = 0: the two finest grids agree (the extrapolation is φ1, the GCI 0)
};

const char* convergence_kind_name(ConvergenceKind k);

struct GridConvergence {
  ConvergenceKind kind = ConvergenceKind::diverging;
  double ratio = 0.0;               // R = ε21 / ε32 (NaN when ε32 = 0)
  double order = 0.0;               // the apparent order p (step 3); NaN unless monotone or oscillatory
  double extrapolated = 0.0;        // φ_ext^21 (step 4): the value as h → 0; NaN when not estimated
  double approximate_error = 0.0;   // e_a^21 = |(φ1 − φ2) / φ1| (step 5)
  double extrapolated_error = 0.0;  // e_ext^21 = |(φ_ext − φ1) / φ_ext| (step 5); NaN when not estimated
  double gci_fine = 0.0;  // GCI_fine^21 = Fs e_a^21 / (r21^p − 1) (step 5); NaN when not estimated
  // The change of φ that one more refinement by r21 would make, as the extrapolation predicts it:
  // (φ_ext − φ1)(1 − r21^−p); NaN when not estimated.
  double next_change = 0.0;
};

// φ1, φ2, φ3 on the fine, medium and coarse grids; r21 = h2 / h1 and r32 = h3 / h2, both > 1
// (`skred refine` halves the cell: 2 and 2). safety_factor Fs: 1.25 for three grids (Roache).
// Throws std::invalid_argument for r ≤ 1 or values that are not finite.
GridConvergence grid_convergence(double phi1, double phi2, double phi3, double r21, double r32,
                                 double safety_factor = 1.25);

}  // namespace skred
