// What a scenario says about the implicit integrator (González Acosta et al. 2020, §2, eq. 3-11,
// 47-48) and the geometry of a 2D grid (App. A1). Plain data: the scenario parses it
// ([implicit], [stage.implicit], [grid] geometry, [[pressure]], [[prescribed_velocity]]), the
// implicit integrator
// (src/implicit) reads it.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace skred {

// Which integrator advances a stage.
enum class IntegratorKind { Explicit, Implicit };

inline const char* to_string(IntegratorKind k) {
  return k == IntegratorKind::Implicit ? "implicit" : "explicit";
}

// A 2D grid's geometry: plane strain, or axisymmetric with x the radius r and y the axis
// (Acosta App. A1: every integral over one radian, weighted by r).
enum class Geometry { PlaneStrain, Axisymmetric };

inline const char* to_string(Geometry g) {
  return g == Geometry::Axisymmetric ? "axisymmetric" : "plane-strain";
}

// Dynamic: Newmark's trapezoidal rule (beta = 1/4, gamma = 1/2; Acosta eq. 8-10). Quasi-static:
// the same equations without inertia (eq. 3 without M a), in load steps.
enum class ImplicitAnalysis { QuasiStatic, Dynamic };

inline const char* to_string(ImplicitAnalysis a) {
  return a == ImplicitAnalysis::Dynamic ? "dynamic" : "quasi-static";
}

// The matrix each Newton iteration solves with: the consistent (algorithmic) tangent of the
// materials (Newton-Raphson), or Acosta's own iteration (§2): the elastic matrix D_p, assembled and
// factorised once per step, with the out-of-balance force re-applied until it vanishes; or
// Acosta's load stepping, one solve with that matrix per step, the step's remaining
// out-of-balance force carried into the next (single).
enum class ImplicitIteration { Newton, Elastic, Single };

inline const char* to_string(ImplicitIteration i) {
  return i == ImplicitIteration::Single ? "single" : i == ImplicitIteration::Elastic ? "elastic" : "newton";
}

// How each linear system is solved: a direct factorisation (Cholesky where the tangent is
// symmetric, LU otherwise) or an iterative Krylov solver with algebraic multigrid.
enum class LinearSolverKind { Direct, Iterative };

inline const char* to_string(LinearSolverKind k) {
  return k == LinearSolverKind::Iterative ? "iterative" : "direct";
}

// How the stiffness and the internal force are integrated (Acosta §5.2-5.4): at the points
// (eq. 5, 7: regular MPM, or GIMP with the GIMP kernel), at the points with the modified weight
// W* = W omp / cmp (eq. 15), or at each cell's Gauss points with the points' stresses and
// tangents mapped there through the cell's nodes (eq. 16-19): by the linear shape functions
// (Gauss mapping, GM), by them with W* (double mapping, DM), or by the local GIMP functions
// S_ip* of the points' support domains (DM-G, eq. 20). W*, GM and DM need the linear kernel,
// DM-G the GIMP one (src/implicit/mapped_stencils.hpp).
enum class ForceIntegration { Points, ModifiedWeights, GaussMapping, DoubleMapping, DoubleMappingGimp };

inline const char* to_string(ForceIntegration f) {
  constexpr const char* names[] = {"points", "modified-weights", "gauss-mapping", "double-mapping",
                                   "double-mapping-gimp"};
  return names[static_cast<int>(f)];
}

// How a point's strain increment is recovered from the nodal displacements: with the kernel's
// gradients at the point (eq. 11), or with the composite material point method's Lagrange
// functions over the point's cell and its neighbours (CMPM, Acosta §5.5, eq. 21-24).
enum class StressRecovery { Points, Cmpm };

inline const char* to_string(StressRecovery r) { return r == StressRecovery::Cmpm ? "cmpm" : "points"; }

// The implicit integrator's settings ([implicit], overridden per stage by [stage.implicit]).
struct ImplicitSettings {
  ImplicitAnalysis analysis = ImplicitAnalysis::QuasiStatic;
  // Dynamic: the time step [s] (0: 10 times the explicit stable step). Quasi-static: the
  // stage's duration is split into load_steps equal steps (its loads follow the stage's
  // gravity ramp and the pressures' ramps over that pseudo-time).
  double time_step = 0.0;
  int load_steps = 1;
  ImplicitIteration iteration = ImplicitIteration::Newton;
  // Convergence: the out-of-balance force's norm below residual_tolerance times the norm of the
  // step's force scale (external plus inertial forces), or the iteration's displacement
  // correction below displacement_tolerance times the step's displacement increment.
  double residual_tolerance = 1e-8;
  double displacement_tolerance = 1e-10;
  int max_iterations = 25;  // Newton iterations per step before it is cut
  bool line_search = true;  // backtracking line search on the residual (PETSc's "bt")
  int max_cuts = 8;         // a step that does not converge is halved at most this often
  // A node whose mass is below this share of a full node's, rho h^D, is a sliver: its weights
  // go to its neighbours (PointStencils::aggregate_slivers).
  double min_node_fill = 1e-4;
  LinearSolverKind linear_solver = LinearSolverKind::Direct;
  std::string petsc_options;  // extra PETSc options ("-ksp_type gmres ..."), for experts
  ForceIntegration integration = ForceIntegration::Points;
  StressRecovery stress_recovery = StressRecovery::Points;
  // Neither remedy: the points integrate and recover with the kernel (the default path).
  bool at_points() const {
    return integration == ForceIntegration::Points && stress_recovery == StressRecovery::Points;
  }
};

// A pressure on a body's face that moves with the material (the hollow cylinder's inner wall,
// Acosta §3.1, fig. 2c-d): on each row (2D) of the body's points, the outermost point towards
// `side` carries it on the edge of its domain, x_p -+ l_p. Positive values push into the body.
struct BoundaryPressure {
  int body = 0;
  int side = 0;            // 2 axis + (0: the body's face towards -axis, 1: towards +axis)
  double pressure = 0.0;   // [Pa] at the end of the ramp
  double ramp_time = 0.0;  // linear ramp from the start of the run, t = 0 [s]; 0: at once
};

// Grid nodes moved at a constant velocity (a rigid footing, plate or wall driven at a rate:
// displacement control): every node with mass inside the box [min, max] has the chosen
// components of its displacement increment prescribed, du = v dt (Dirichlet conditions like the
// walls'); the others stay free (a smooth footing holds only the normal one). The force the
// nodes exert on the material (the supports' reactions, -R on the held rows) is reported.
inline constexpr int kMaxPrescribed = 4;  // [[prescribed_velocity]] tables per scenario
struct PrescribedVelocity {
  std::string name;
  std::array<double, 3> min{}, max{}, velocity{};  // [m], [m], [m/s]; D components used
  std::uint8_t components = 0b111;                 // bit c: component c is prescribed
};

// The prescribed boundaries' forces on the material, D per boundary [N/m in 2D, N per radian
// axisymmetric, N in 3D], at the integrator's time (kept with the clock for the work's trapezoid).
using BoundaryForces = std::array<double, 3 * kMaxPrescribed>;

}  // namespace skred
