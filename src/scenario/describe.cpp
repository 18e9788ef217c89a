// The human summary of a scenario printed by `skred check`.
#include <fmt/format.h>

#include <cmath>
#include <type_traits>

#include "scenario/build.hpp"
#include "scenario/estimate.hpp"

namespace skred {
namespace {

// The strength parameters of a material, for describe().
std::string strength_summary(const Material& m) {
  constexpr double deg = 180.0 / M_PI;
  switch (m.model) {
    case Model::LinearElastic: return "";
    case Model::MohrCoulomb: {
      const auto& mc = m.mohr_coulomb;
      std::string t = fmt::format(", friction {:.4g} deg, cohesion {} Pa, dilation {:.4g} deg",
                                  mc.friction * deg, mc.cohesion, mc.dilation * deg);
      if (std::isfinite(mc.tension_cutoff)) t += fmt::format(", tension cut-off {} Pa", mc.tension_cutoff);
      if (mc.max_void_ratio > 0)
        t += fmt::format(", void ratio {} -> max {}", mc.initial_void_ratio, mc.max_void_ratio);
      return t;
    }
    case Model::Tresca: return fmt::format(", cohesion {} Pa", m.mohr_coulomb.cohesion);
    case Model::VonMises:
      return fmt::format(", cohesion {} Pa -> residual {} Pa, softening modulus {} Pa",
                         m.von_mises.cohesion_peak, m.von_mises.cohesion_residual,
                         m.von_mises.softening_modulus);
  }
  return "";
}

std::string bytes_text(double bytes) {
  if (bytes >= 1e9) return fmt::format("{:.3g} GB", bytes / 1e9);
  if (bytes >= 1e6) return fmt::format("{:.3g} MB", bytes / 1e6);
  return fmt::format("{:.3g} kB", bytes / 1e3);
}

// The integrator of a stage; `auto_step`: a dynamic implicit stage's time step when its
// implicit.time_step is 0.
std::string integrator_summary(const Stage& st, double auto_step) {
  if (st.integrator == IntegratorKind::Explicit) return ", explicit integrator";
  const ImplicitSettings& im = st.implicit;
  std::string t = fmt::format(", implicit integrator ({}", to_string(im.analysis));
  if (im.analysis == ImplicitAnalysis::QuasiStatic)
    t += fmt::format(" in {} load step{}", im.load_steps, im.load_steps == 1 ? "" : "s");
  else if (im.time_step > 0.0)
    t += fmt::format(", time step {} s", im.time_step);
  else
    t += fmt::format(", time step {:.4g} s ({:g} x the stable explicit step)", auto_step, kAutoImplicitSteps);
  t += fmt::format(", {} iteration, {} linear solver", to_string(im.iteration), to_string(im.linear_solver));
  if (!im.at_points())
    t += fmt::format(", integration {}, stress recovery {}", to_string(im.integration),
                     to_string(im.stress_recovery));
  return t + ")";
}

std::string stage_summary(const ScenarioCommon& s, const Stage& st) {
  std::string t = fmt::format("  {}: {} s", st.name, st.duration);
  if (st.gravity_ramp_time > 0) t += fmt::format(", gravity ramp {} s", st.gravity_ramp_time);
  if (st.elastic) t += ", held elastic";
  if (st.strength_reduction != 1.0) t += fmt::format(", strength reduction {}", st.strength_reduction);
  for (const auto& o : st.overrides) {
    t += fmt::format(", {}:", s.materials[static_cast<std::size_t>(o.material)].name);
    if (o.friction) t += fmt::format(" friction {:.4g} deg", *o.friction * 180.0 / M_PI);
    if (o.cohesion) t += fmt::format(" cohesion {} Pa", *o.cohesion);
    if (o.dilation) t += fmt::format(" dilation {:.4g} deg", *o.dilation * 180.0 / M_PI);
    if (o.density) t += fmt::format(" density {} kg/m^3 (over {} s)", *o.density, o.density_ramp_time);
  }
  if (st.rest_speed > 0) {
    const Stage::RestMeasure r = rest_measure_of(s, st);
    t += r == Stage::RestMeasure::Displacement
             ? fmt::format(", ends when the points move on average slower than {} m/s over {} s",
                           st.rest_speed, st.rest_time)
             : fmt::format(", ends when the {} mean speed stays below {} m/s for {} s",
                           r == Stage::RestMeasure::Material ? "material's" : "points'", st.rest_speed,
                           st.rest_time);
  }
  if (st.runout_thickness > 0)
    t += fmt::format(", runout where the deposit is {} m thick", st.runout_thickness);
  return t;
}

std::string vec(const Vec<2>& v) { return fmt::format("({}, {})", v[0], v[1]); }
std::string vec(const Vec<3>& v) { return fmt::format("({}, {}, {})", v[0], v[1], v[2]); }

std::string shape_summary(const Shape& shape) {
  return std::visit(
      [](const auto& sh) -> std::string {
        using T = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<T, Rectangle>) {
          return fmt::format("rectangle {} to {}", vec(sh.min), vec(sh.max));
        } else if constexpr (std::is_same_v<T, Disc>) {
          return fmt::format("disc centre {} radius {} m", vec(sh.center), sh.radius);
        } else if constexpr (std::is_same_v<T, Layer>) {
          return fmt::format("layer between profiles of {} and {} points{}, area {:.6g} m^2",
                             sh.bottom.points.size(), sh.top.points.size(),
                             sh.surface ? " below the ground surface" : "", layer_area(sh));
        } else {
          return fmt::format("polygon with {} vertices, area {} m^2", sh.vertices.size(),
                             std::abs(polygon_area(sh)));
        }
      },
      shape);
}

std::string shape_summary(const Shape3& shape) {
  return std::visit(
      [](const auto& sh) -> std::string {
        using T = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<T, Box>) {
          return fmt::format("box {} to {}", vec(sh.min), vec(sh.max));
        } else if constexpr (std::is_same_v<T, Sphere>) {
          return fmt::format("sphere centre {} radius {} m", vec(sh.center), sh.radius);
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          return fmt::format("cylinder centre {} axis {} radius {} m length {} m", vec(sh.center),
                             vec(sh.axis), sh.radius, sh.length);
        } else if constexpr (std::is_same_v<T, Layer3>) {
          return fmt::format("layer between rasters {} and {}{}, volume {:.6g} m^3", sh.top->file,
                             sh.bottom ? sh.bottom->file : "the grid's bottom",
                             sh.surface ? " below the ground surface" : "", layer_volume(sh));
        } else {
          return fmt::format("polygon with {} vertices, area {} m^2, extruded over z {} to {}",
                             sh.section.vertices.size(), std::abs(polygon_area(sh.section)), sh.z_min,
                             sh.z_max);
        }
      },
      shape);
}

std::string boundary_summary(const BoundarySide& b) {
  if (b.kind == BoundaryKind::Friction) return fmt::format("friction (mu = {})", b.friction);
  return to_string(b.kind);
}

}  // namespace

template <int D>
std::string describe(const ScenarioOf<D>& s) {
  std::string out;
  auto line = [&out](const std::string& text) { out += text + '\n'; };
  line(fmt::format("scenario: {}{}", s.source, s.title.empty() ? "" : " (\"" + s.title + "\")"));
  std::string cells, extent;
  for (int d = 0; d < D; ++d) {
    cells += fmt::format("{}{}", d ? " x " : "", s.cells[static_cast<std::size_t>(d)]);
    extent += fmt::format("{}{}", d ? " x " : "", s.cells[static_cast<std::size_t>(d)] * s.cell_size);
  }
  line(fmt::format("grid{}: {} cells of {} m, origin {}, extent {} m", D == 3 ? " (3D)" : "", cells,
                   s.cell_size, vec(s.origin), extent));
  if (s.geometry == Geometry::Axisymmetric)
    line("geometry: axisymmetric (x is the radius r, y the axis; masses and volumes per radian)");
  line(fmt::format("materials ({}):", s.materials.size()));
  for (const auto& m : s.materials)
    line(fmt::format("  {}: {}, density {} kg/m^3, young {} Pa, poisson {}{}", m.name, to_string(m.model),
                     m.density, m.elastic.young, m.elastic.poisson, strength_summary(m)));
  line(fmt::format("bodies ({}):", s.bodies.size()));
  for (const auto& b : s.bodies) {
    if (b.dilated_from >= 0) {  // Paper III §C.3.2
      line(fmt::format("  {}: dilated continuum of {} (starts empty; its points reach max_void_ratio)",
                       b.name, s.bodies[static_cast<std::size_t>(b.dilated_from)].name));
      continue;
    }
    const std::string mat = b.material >= 0 && static_cast<std::size_t>(b.material) < s.materials.size()
                                ? s.materials[static_cast<std::size_t>(b.material)].name
                                : "?";
    line(fmt::format("  {}: {}, material {}, {} points per cell, velocity {} m/s{}", b.name,
                     shape_summary(b.shape), mat,
                     D == 3 ? fmt::format("{0}x{0}x{0}", b.particles_per_cell)
                            : fmt::format("{0}x{0}", b.particles_per_cell),
                     vec(b.velocity), b.rigid ? ", rigid" : ""));
    if (b.lattice_rotation != 0.0)  // Acosta §6, fig. 19
      line(fmt::format("    its points on a lattice turned {:.4g} deg about {} m",
                       b.lattice_rotation * 180.0 / M_PI, vec(b.lattice_centre)));
  }
  for (const ContactPair& c : s.contacts)  // Paper III §C.2.7
    line(fmt::format("contact: {} - {}, friction {}, detection {}",
                     s.bodies[static_cast<std::size_t>(c.a)].name,
                     s.bodies[static_cast<std::size_t>(c.b)].name, c.friction,
                     c.detection == ContactDetection::Traction ? "traction" : "fill"));
  line(fmt::format("gravity: {} m/s^2", vec(s.gravity)));
  switch (s.initial_stress.rule) {
    case K0Rule::None: break;
    case K0Rule::Poisson: line("initial stress: K0 = nu / (1 - nu) from the overburden"); break;
    case K0Rule::Jaky: line("initial stress: K0 = 1 - sin(phi) from the overburden"); break;
    case K0Rule::Value:
      line(fmt::format("initial stress: K0 = {} from the overburden", s.initial_stress.k0));
      break;
  }
  for (const BoundaryPressure& p : s.pressures) {
    static const char* const faces[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    line(fmt::format("pressure: {} Pa on the {} face of body {}{}", p.pressure, faces[p.side],
                     s.bodies[static_cast<std::size_t>(p.body)].name,
                     p.ramp_time > 0.0 ? fmt::format(", ramped over {} s", p.ramp_time) : ""));
  }
  for (const PrescribedVelocity& pv : s.prescribed) {
    std::string comps, lo, hi, v;
    for (int d = 0; d < D; ++d) {
      const auto k = static_cast<std::size_t>(d);
      if ((pv.components >> d) & 1u) comps += "xyz"[d];
      lo += fmt::format("{}{}", d ? ", " : "", pv.min[k]);
      hi += fmt::format("{}{}", d ? ", " : "", pv.max[k]);
      v += fmt::format("{}{}", d ? ", " : "", pv.velocity[k]);
    }
    line(fmt::format("prescribed velocity \"{}\": the nodes in [{}] to [{}] driven at [{}] m/s ({} held)",
                     pv.name, lo, hi, v, comps));
  }
  line(fmt::format("stages ({}):", s.stages.size()));
  for (const auto& st : s.stages)
    line(stage_summary(s, st) +
         integrator_summary(st, st.integrator == IntegratorKind::Implicit ? implicit_time_step(s, st) : 0.0));
  if (s.any_implicit()) {
    const ImplicitSystemSize z = estimate_implicit_system(s);
    line(
        fmt::format("implicit system: about {:.3g} unknowns ({} per grid node of the cells the bodies' "
                    "bounding boxes cover; an estimate)",
                    z.unknowns, D));
    bool direct = false;
    for (const Stage& st : s.stages)
      direct = direct || (st.integrator == IntegratorKind::Implicit &&
                          st.implicit.linear_solver == LinearSolverKind::Direct);
    if (direct) {
      const std::string how = D == 2 ? fmt::format("MUMPS' measured {:g} B x N log2 N", kDirectBytes2)
                                     : fmt::format("MUMPS' measured {:g} B x N^(4/3)", kDirectBytes3);
      line(fmt::format("  direct solver: about {} for the factorisation (an estimate: {}){}",
                       bytes_text(z.direct_bytes), how,
                       z.direct_bytes > 0.8 * available_memory_bytes()
                           ? fmt::format("; more than this machine offers ({}): use linear_solver = "
                                         "\"iterative\"",
                                         bytes_text(available_memory_bytes()))
                           : ""));
    }
  }
  static const char* const names[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  std::string sides;
  for (int k = 0; k < 2 * D; ++k)
    sides += fmt::format(
        "{}{} {}", k ? ", " : "", names[k],
        boundary_summary(s.boundaries[static_cast<std::size_t>(k)]) +
            (k == 0 && s.geometry == Geometry::Axisymmetric && s.origin[0] == 0.0 ? " (the axis)" : ""));
  line("boundaries: " + sides);
  std::string interp = to_string(s.interpolation);
  if (s.interpolation == Interpolation::GimpQuadrature)
    interp += fmt::format(" ({} points per direction)", s.quadrature_points);
  const std::string step = s.time_step > 0.0 ? fmt::format("time step {} s", s.time_step)
                                             : fmt::format("time step from CFL {}", s.cfl);
  bool explicit_stages = false, implicit_stages = false;
  for (const Stage& st : s.stages)
    (st.integrator == IntegratorKind::Explicit ? explicit_stages : implicit_stages) = true;
  line(fmt::format("solver: {} interpolation, {} scheme, end time {} s{}", interp, to_string(s.scheme),
                   s.end_time,
                   !explicit_stages  ? ""
                   : implicit_stages ? ", " + step + " (explicit stages)"
                                     : ", " + step));
  std::string transfer = to_string(s.velocity_transfer);
  if (s.velocity_transfer == VelocityTransfer::Xpic) {
    transfer += fmt::format("({})", s.xpic_order);
    transfer += s.xpic_period > 0.0 ? fmt::format(" once per {} h/c", s.xpic_period) : " every step";
  }
  if (s.velocity_transfer == VelocityTransfer::Flip && s.pic_fraction > 0.0)
    transfer += fmt::format(" with PIC share {}", s.pic_fraction);
  if (s.transfer_by_default) transfer += " (by \"auto\")";
  line(fmt::format("velocity transfer: {}; volumetric strain: {}{}", transfer,
                   s.volumetric_averaging ? "cell-average" : "point",
                   s.centre_shear ? "; shear strain: cell-centre (Thesis §4.5)" : ""));
  // FLIP and the affine FLIP at a frictional wall (docs/method.md, "How FLIP lifts the block")
  bool rubs = false;
  for (int k = 0; k < 2 * D; ++k)
    rubs = rubs || s.boundaries[static_cast<std::size_t>(k)].kind == BoundaryKind::Friction;
  if (keeps_null_space(s) && rubs)
    line(
        "  note: this transfer keeps velocities the grid cannot see, and a frictional wall turns part of "
        "them into lift: material sliding on it rises off the wall and loses less to friction than it "
        "should (docs/method.md, \"How FLIP lifts the block\"); \"xpic\" and \"apic\" do not");
  line(fmt::format("output: particle frames every {} s, series rows every {} s", s.output_interval,
                   s.series_interval));
  return out;
}

template std::string describe<2>(const Scenario&);
template std::string describe<3>(const Scenario3&);

}  // namespace skred
