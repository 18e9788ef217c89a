// The scenario schema's sections of the run (see schema.cpp): initial stress, gravity,
// boundaries, solver, stages and output.
#include "scenario/output_fields.hpp"
#include "scenario/schema_sections.hpp"

namespace skred::schema::detail {

void add_run_sections(std::vector<Section>& s) {
  s.push_back({"initial_stress",
               "initial-stress",
               {
                   {.name = "k0",
                    .type = Type::K0,
                    .range = Range::closed(0.0, 10.0),
                    .choices = "poisson|jaky",
                    .doc = "\"poisson\": K0 = nu/(1 - nu) (Thesis eq. 5.7); \"jaky\": K0 = 1 - sin(phi) "
                           "(Post eq. 51; materials without friction use nu/(1 - nu)); or a number"},
               }});
  s.push_back({"gravity",
               "gravity",
               {
                   {.name = "acceleration",
                    .type = Type::Vector,
                    .unit = "m/s^2",
                    .def = derived("0"),
                    .range = Range::closed(-kMaxGravity, kMaxGravity),
                    .doc = "g, for example [0, -9.81]"},
                   {.name = "ramp_time",
                    .unit = "s",
                    .def = value(0),
                    .range = Range::non_negative(kMaxTime),
                    .doc = "sine ramp of Thesis eq. 4.13; 0: full gravity from the first step"},
               }});
  s.push_back(
      {"boundary",
       "boundary",
       {
           {.name = "x_min",
            .type = Type::Side,
            .def = derived("\"free\""),
            .doc = "the wall x = origin_x (axisymmetric from x = 0: the axis, a roller)"},
           {.name = "x_max",
            .type = Type::Side,
            .def = derived("\"free\""),
            .doc = "the wall x = origin_x + Lx"},
           {.name = "y_min", .type = Type::Side, .def = derived("\"free\""), .doc = "the wall y = origin_y"},
           {.name = "y_max",
            .type = Type::Side,
            .def = derived("\"free\""),
            .doc = "the wall y = origin_y + Ly"},
           {.name = "z_min", .type = Type::Side, .def = derived("\"free\""), .doc = "3D only: z = origin_z"},
           {.name = "z_max",
            .type = Type::Side,
            .def = derived("\"free\""),
            .doc = "3D only: z = origin_z + Lz"},
       }});
  s.push_back(
      {"boundary.side",
       "boundary-side",
       {
           {.name = "type",
            .type = Type::Choice,
            .choices = "free|fixed|roller|friction",
            .doc = "free: no constraint; fixed: no-slip; roller: free slip; friction: Coulomb friction "
                   "(Thesis eq. 5.8-5.11)"},
           {.name = "friction",
            .unit = "-",
            .def = derived("required with type = \"friction\""),
            .range = Range::non_negative(10.0),
            .doc = "the coefficient mu; only with type = \"friction\""},
       }});
  s.push_back(
      {"pressure",
       "pressure",
       {
           {.name = "body", .type = Type::String, .doc = "the `name` of a [[body]]"},
           {.name = "side",
            .type = Type::Choice,
            .choices = "x_min|x_max|y_min|y_max|z_min|z_max",
            .doc = "the body's face: on each row of its points the outermost one towards this side of "
                   "the grid carries the pressure on the edge of its domain (z_min, z_max in 3D only)"},
           {.name = "value",
            .unit = "Pa",
            .range = Range::closed(-1e12, 1e12),
            .doc = "the pressure at the end of the ramp; positive pushes into the body"},
           {.name = "ramp_time",
            .unit = "s",
            .def = value(0),
            .range = Range::non_negative(kMaxTime),
            .doc = "linear ramp from the start of the run (t = 0); 0: the full pressure at once"},
       }});
  s.push_back(
      {"prescribed_velocity",
       "prescribed_velocity",
       {
           {.name = "name",
            .type = Type::String,
            .def = derived("\"prescribed<i>\""),
            .doc = "names the boundary in series.csv's force columns (force_<name>_x, ...) and summary.json"},
           {.name = "min",
            .type = Type::Vector,
            .unit = "m",
            .range = kCoordinate,
            .doc = "the low corner of the box whose grid nodes are driven"},
           {.name = "max",
            .type = Type::Vector,
            .unit = "m",
            .range = kCoordinate,
            .doc = "the high corner; the box holds at least one grid node"},
           {.name = "velocity",
            .type = Type::Vector,
            .unit = "m/s",
            .range = kVelocity,
            .doc = "the nodes' velocity (quasi-static: displacement per unit of the stage's pseudo-time)"},
           {.name = "components",
            .type = Type::Choice,
            .def = derived("\"all\""),
            .choices = "all|x|y|z",
            .doc = "the components prescribed; the others stay free (\"all\": a rough footing; the normal "
                   "axis alone: a smooth one)"},
       }});
  s.push_back(
      {"solver",
       "solver",
       {
           {.name = "integrator",
            .type = Type::Choice,
            .def = derived("\"explicit\""),
            .choices = "explicit|implicit",
            .doc = "how every stage without its own `integrator` is advanced: \"explicit\", the central "
                   "difference update of Thesis §2.2, or \"implicit\", Newton iterations on the grid's "
                   "equilibrium equations (González Acosta et al. 2020; [implicit] below)"},
           {.name = "interpolation",
            .type = Type::Choice,
            .def = derived("\"gimp\""),
            .choices = "linear|gimp|gimp-quadrature|bspline",
            .doc = "the weighting functions (Thesis §2.2, §3.3)"},
           {.name = "quadrature_points",
            .type = Type::Integer,
            .def = value(2),
            .range = Range::closed(1, 3),
            .doc = "points per direction for \"gimp-quadrature\" (Thesis eq. 3.16-3.22); ignored otherwise"},
           {.name = "scheme",
            .type = Type::Choice,
            .def = derived("\"averaged\""),
            .choices = "usf|usl|averaged",
            .doc = "the stress update scheme (Thesis §4.4)"},
           {.name = "end_time",
            .unit = "s",
            .def = derived("required without [[stage]]"),
            .range = Range::positive(kMaxTime),
            .doc = "not allowed with [[stage]] tables: their durations add up to the end time"},
           {.name = "time_step",
            .unit = "s",
            .def = none("from `cfl`"),
            .range = Range::closed(kMinTimeStep, kMaxTimeStep),
            .doc = "a fixed time step; must not exceed the stable step h / c (see below)"},
           {.name = "cfl",
            .unit = "-",
            .def = value(0.3),
            .range = Range{0.0, 1.0, true, false},
            .doc = "dt = cfl h / (c + v0), c the fastest P-wave speed, v0 the fastest initial speed"},
           {.name = "allow_unstable_time_step",
            .type = Type::Boolean,
            .def = derived("false"),
            .doc = "true accepts a `time_step` above the stable step with a warning"},
           {.name = "elastic_update",
            .type = Type::Choice,
            .def = derived("\"incremental\""),
            .choices = "incremental|hyperelastic",
            .doc = "linear-elastic materials: \"incremental\", sigma^k + C : d_eps pushed forward "
                   "through dF (Thesis eq. 4.1-4.4), or \"hyperelastic\", the stress of the stored "
                   "energy W = G sum (l_i - 1)^2 + lambda/2 (sum (l_i - 1))^2 of F, which stores and "
                   "returns exactly the energy of F at large elastic strains (docs/method.md)"},
           {.name = "velocity_transfer",
            .type = Type::Choice,
            .def = derived("\"auto\""),
            .choices = "auto|flip|xpic|apic|aflip",
            .doc =
                "the particle velocity update (docs/method.md, \"Velocity transfers\"): FLIP (Thesis "
                "eq. 2.56, with `pic_fraction`), XPIC(m) (Hammerquist & Nairn 2017), APIC (Jiang et "
                "al. 2015) or the affine FLIP (Fei et al. 2021: FLIP's update with APIC's map; its "
                "points keep FLIP's grid-invisible velocities, so a deposit whose motion has stopped "
                "may not reach a rest speed). FLIP, XPIC and APIC work with [[contact]] and rigid bodies; "
                "the affine FLIP is refused with [[contact]] (it gains energy there). \"auto\": \"xpic\" "
                "with `xpic_period` 2 when a deformable body's material can yield (a slide comes to rest and "
                "its runout does not follow the time step), else \"flip\" (keeps the energy of elastic "
                "dynamics); `pic_fraction` alone picks \"flip\", `xpic_order` or `xpic_period` alone "
                "\"xpic\" (docs/method.md, \"The defaults\")"},
           {.name = "xpic_order",
            .type = Type::Integer,
            .def = value(2),
            .range = Range::closed(1, 20),
            .doc = "\"xpic\" only: the m of XPIC(m); 1 is PIC; each order above 1 costs one more pass "
                   "over the points"},
           {.name = "xpic_period",
            .unit = "h/c",
            .def = derived("2 with velocity_transfer \"auto\", else 0"),
            .range = Range{0.0, 1.0e6, false, false},
            .doc = "\"xpic\" only: 0 filters every step; above 0, FLIP at every step and XPIC(m) once per "
                   "this many crossing times of a cell by the fastest P wave, h / (c + v0) (the step at "
                   "cfl = 1), so the filter's damping per second does not depend on the time step "
                   "(docs/method.md, \"The filter per unit time\")"},
           {.name = "volumetric_strain",
            .type = Type::Choice,
            .def = derived("\"auto\""),
            .choices = "auto|point|cell-average",
            .doc = "\"auto\": \"cell-average\" when a deformable body's material can yield, else "
                   "\"point\"; \"point\": each point's own strain increment (Thesis eq. 2.20); "
                   "\"cell-average\": the volume-weighted mean volumetric strain of the points in its cell "
                   "with its own "
                   "deviatoric strain, and the cell's mean pressure in the internal force (B-bar "
                   "against volumetric locking in isochoric plastic flow; docs/method.md); every scheme"},
           {.name = "shear_strain",
            .type = Type::Choice,
            .def = derived("\"point\""),
            .choices = "point|cell-centre",
            .doc = "\"point\": each point's own shear strain increment; \"cell-centre\": selective "
                   "integration of shear (Thesis §4.5), the shape functions' gradients at the centre of "
                   "the point's cell in the shear strain rate and the shear stresses' internal force, "
                   "against parasitic shear in bending (docs/method.md); scheme \"usf\" with "
                   "volumetric_strain \"point\""},
           {.name = "pic_fraction",
            .unit = "-",
            .def = value(0),
            .range = Range::closed(0.0, 1.0),
            .doc = "PIC share a of the particle velocity update: v_p = (1 - a) v_FLIP + a sum N_ip "
                   "v_i^{k+1}; 0 is the force-based update of Thesis eq. 2.56; \"flip\" only"},
       }});
  s.push_back(
      {"implicit",
       "implicit",
       {
           {.name = "analysis",
            .type = Type::Choice,
            .def = derived("\"quasi-static\""),
            .choices = "quasi-static|dynamic",
            .doc = "\"quasi-static\": equilibrium without inertia, the stage's loads applied in "
                   "`load_steps` steps; \"dynamic\": Newmark's trapezoidal rule (beta = 1/4, gamma = 1/2; "
                   "Acosta eq. 8-10) with `time_step`"},
           {.name = "time_step",
            .unit = "s",
            .def = value(0),
            .range = Range::non_negative(kMaxTimeStep),
            .doc = "\"dynamic\" only: the time step; 0: 10 times the stable explicit step h / (c + v0)"},
           {.name = "load_steps",
            .type = Type::Integer,
            .def = value(1),
            .range = Range::closed(1, 1e6),
            .doc = "\"quasi-static\" only: the stage's duration in this many equal steps, its gravity "
                   "ramp and pressure ramps followed over that pseudo-time"},
           {.name = "iteration",
            .type = Type::Choice,
            .def = derived("\"newton\""),
            .choices = "newton|elastic|single",
            .doc = "\"newton\": Newton-Raphson with the materials' consistent tangent; \"elastic\": the "
                   "elastic matrix, factorised once per step, the out-of-balance force re-applied until it "
                   "vanishes (Acosta §2); \"single\": Acosta's load stepping, one solve with the elastic "
                   "matrix per step, the remaining out-of-balance force carried into the next step (the "
                   "default of a Gauss-mapped integration in a stage whose materials are all elastic)"},
           {.name = "residual_tolerance",
            .unit = "-",
            .def = value(1e-8),
            .range = Range{0.0, 1.0, true, true},
            .doc = "a step has converged when the out-of-balance force's norm is below this times the "
                   "step's force scale (external plus inertial forces)"},
           {.name = "displacement_tolerance",
            .unit = "-",
            .def = value(1e-10),
            .range = Range{0.0, 1.0, true, true},
            .doc = "... or when the iteration's displacement correction is below this times the step's "
                   "displacement increment"},
           {.name = "max_iterations",
            .type = Type::Integer,
            .def = value(25),
            .range = Range::closed(1, 1000),
            .doc = "iterations per step before the step is cut"},
           {.name = "line_search",
            .type = Type::Boolean,
            .def = derived("true"),
            .doc = "a backtracking line search on the residual (PETSc's \"bt\")"},
           {.name = "max_cuts",
            .type = Type::Integer,
            .def = value(8),
            .range = Range::closed(0, 30),
            .doc = "a step that does not converge is halved at most this often"},
           {.name = "min_node_fill",
            .unit = "-",
            .def = value(1e-4),
            .range = Range{0.0, 1.0, true, true},
            .doc = "a node whose mass is below this share of a full node's (the densest material's rho h^D) "
                   "is a sliver: it hands its weights to its neighbour towards each point, since a sliver "
                   "of width e carries a force of order e against a mass and stiffness of order e^2 and "
                   "would run off"},
           {.name = "linear_solver",
            .type = Type::Choice,
            .def = derived("\"direct\""),
            .choices = "direct|iterative",
            .doc = "\"direct\": a sparse factorisation (Cholesky where the tangent is symmetric, LU "
                   "otherwise); \"iterative\": a Krylov solver with algebraic multigrid, for systems too "
                   "large to factorise (`skred check` estimates the factorisation's memory)"},
           {.name = "petsc_options",
            .type = Type::String,
            .def = derived("\"\""),
            .doc = "extra PETSc options, e.g. \"-ksp_type gmres\", for experts"},
           {.name = "integration",
            .type = Type::Choice,
            .def = derived("\"points\""),
            .choices = "points|modified-weights|gauss-mapping|double-mapping|double-mapping-gimp",
            .doc = "how the stiffness and internal force are integrated (Acosta §5.2-5.4): at the points; "
                   "with W* = W omp / cmp; at the cells' Gauss points with the points' stresses mapped "
                   "there by the linear shape functions (GM), and with W* (DM); or by the local GIMP "
                   "functions (DM-G). W*, GM and DM need interpolation = \"linear\", DM-G \"gimp\""},
           {.name = "stress_recovery",
            .type = Type::Choice,
            .def = derived("\"points\""),
            .choices = "points|cmpm",
            .doc = "how a point's strain increment is recovered: with the kernel's gradients at the point, "
                   "or with the composite material point method's cubic Lagrange functions over its cell "
                   "and neighbours (CMPM, Acosta §5.5); \"linear\" or \"gimp\" interpolation"},
       }});
  s.push_back(
      {"stage",
       "stage",
       {
           {.name = "name", .type = Type::String, .def = derived("\"stage-I\""), .doc = "any"},
           {.name = "duration",
            .unit = "s",
            .range = Range::positive(kMaxTime),
            .doc = "the stage's length: an implicit stage ends at this time; an explicit one runs whole time "
                   "steps, at least one, the last of which may pass it by less than a step"},
           {.name = "gravity_ramp_time",
            .unit = "s",
            .def = value(0),
            .range = Range::non_negative(kMaxTime),
            .doc = "<= duration; sine ramp of Thesis eq. 4.13 from the stage start; 0: full gravity"},
           {.name = "elastic",
            .type = Type::Boolean,
            .def = derived("false"),
            .doc = "true holds every material linear elastic (an equilibrium stage)"},
           {.name = "strength_reduction",
            .unit = "-",
            .def = value(1),
            .range = Range::closed(0.1, 100.0),
            .doc = "c, tan(phi) and tan(psi) are divided by it (below 1: a stronger soil; `skred fos` "
                   "bisects it)"},
           {.name = "material",
            .type = Type::Tables,
            .def = none(),
            .doc = "strength changes for this stage (stage.material, below)"},
           {.name = "rest_speed",
            .unit = "m/s",
            .def = value(0),
            .range = Range::non_negative(kMaxSpeed),
            .doc = "0: off; the stage also ends once the mean speed (Thesis eq. 5.12) has stayed "
                   "below it for `rest_time`"},
           {.name = "rest_time",
            .unit = "s",
            .def = derived("required with rest_speed"),
            .range = Range::positive(kMaxTime),
            .doc = "see `rest_speed`"},
           {.name = "rest_measure",
            .type = Type::Choice,
            .def = derived("\"auto\""),
            .choices = "auto|points|material|displacement",
            .doc = "the speed `rest_speed` is compared with: the points' own mean speed (\"points\", eq. "
                   "5.12), the material's, sum_i N_ip v_i at each point (\"material\", eq. 2.55: what "
                   "moves it), or the points' mean displacement over windows of `rest_time`, over "
                   "`rest_time` (\"displacement\": a deposit ringing in place rests); \"auto\" takes the "
                   "material's with pure FLIP and the affine FLIP, whose points keep velocities the grid "
                   "cannot see, the points' otherwise (docs/method.md, \"The rest test\")"},
           {.name = "runout_thickness",
            .unit = "m",
            .def = derived("half a cell"),
            .range = Range::positive(1e4),
            .doc = "the stage's runout (summary.json, series.csv) ends where the deposit raises the "
                   "original surface by less than this; a thickness in metres keeps the measure "
                   "from shrinking with the cell (docs/method.md, \"Runout at a thickness\")"},
           {.name = "local_damping",
            .unit = "-",
            .def = value(0),
            .range = Range::closed(0.0, 0.99),
            .doc = "0: off; Cundall-type local damping alpha for an equilibrium stage: each node feels "
                   "-alpha |f| sign(v) per component (f its unbalanced force); its work is the "
                   "series.csv column `damping_work`; with contact, on each body's nodes except the "
                   "interface's; explicit stages only"},
           {.name = "integrator",
            .type = Type::Choice,
            .def = derived("solver.integrator"),
            .choices = "explicit|implicit",
            .doc = "the stage's integrator"},
           {.name = "implicit",
            .type = Type::Table,
            .def = none("[implicit]'s"),
            .doc = "changes to [implicit] for this stage, any of its keys (`[stage.implicit]` after the "
                   "`[[stage]]`); implicit stages only"},
       }});
  s.push_back({"stage.material",
               "stage-material",
               {
                   {.name = "name", .type = Type::String, .doc = "the `name` of a [[material]]"},
                   {.name = "friction",
                    .unit = "deg",
                    .def = none("the material's"),
                    .range = Range{0.0, 90.0, false, true},
                    .doc = "phi; mohr-coulomb only"},
                   {.name = "cohesion",
                    .unit = "Pa",
                    .def = none("the material's"),
                    .range = Range::non_negative(1e12),
                    .doc = "c (> 0 for tresca and von-mises, whose residual cohesion it scales too)"},
                   {.name = "dilation",
                    .unit = "deg",
                    .def = none("the material's"),
                    .range = Range{0.0, 90.0, false, true},
                    .doc = "psi <= phi; mohr-coulomb only"},
                   {.name = "density",
                    .unit = "kg/m^3",
                    .def = none("unchanged"),
                    .range = Range::closed(1e-3, 1e6),
                    .doc = "a trigger (Paper III §C.3, rainfall): the points' density becomes this, over "
                           "`density_ramp_time`, and stays so in later stages"},
                   {.name = "density_ramp_time",
                    .unit = "s",
                    .def = value(0),
                    .range = Range::non_negative(kMaxTime),
                    .doc = "<= the stage duration; the density follows (1 - cos(pi t / T)) / 2 from the "
                           "stage start; 0: at once"},
               }});
  s.push_back({"output",
               "output",
               {
                   {.name = "interval",
                    .unit = "s",
                    .def = derived("end_time / 20"),
                    .range = Range::positive(kMaxTime),
                    .doc = "simulated time between particle frames; at most 100000 frames"},
                   {.name = "series_interval",
                    .unit = "s",
                    .def = derived("interval / 10"),
                    .range = Range::positive(kMaxTime),
                    .doc = "simulated time between rows of series.csv; at most 10^7 rows"},
                   {.name = "fields",
                    .type = Type::Fields,
                    .def = derived(output_fields::kDefault),
                    .choices = output_fields::kAll,
                    .doc = "the cell fields of each particle frame: `\"default\"` (the default column), "
                           "`\"all\"`, or a list of names, which may hold `\"default\"`; "
                           "docs/post-processing.md describes each"},
                   {.name = "compression",
                    .type = Type::Boolean,
                    .def = derived("true"),
                    .doc = "zlib-compress the arrays of the particle and grid frames (VTK's "
                           "vtkZLibDataCompressor; ParaView reads both)"},
                   {.name = "maps",
                    .type = Type::Boolean,
                    .def = derived("true"),
                    .doc = "3D only: write the hazard maps (deposit thickness, change of height, largest "
                           "speed and displacement, arrival time) as .asc and GeoTIFF under maps/"},
                   {.name = "map_threshold",
                    .unit = "m",
                    .def = derived("cell_size / 2"),
                    .range = Range::positive(1e6),
                    .doc = "3D only: a point has moved once it lies further than this from its place at "
                           "the stage start (the deposit and the arrival of the hazard maps)"},
               }});
}

}  // namespace skred::schema::detail
