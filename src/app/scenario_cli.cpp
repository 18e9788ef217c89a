#include "app/scenario_cli.hpp"

#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <variant>

#include "run/slope_stability.hpp"
#include "scenario/build.hpp"
#include "scenario/estimate.hpp"
#include "scenario/scenario.hpp"
#include "scenario/schema.hpp"

namespace skred {

namespace {

// Above this many estimated points `check` reports the estimate instead of generating them.
constexpr double kCountPointsUpTo = 2e6;

std::string gigabytes(double bytes) { return fmt::format("{:.3g} GB", bytes / 1e9); }

template <int D>
void refuse_if_too_big(const ScenarioOf<D>& s, const ScenarioSize& z) {
  const double available = available_memory_bytes();
  if (z.memory_bytes > 0.8 * available)
    throw ScenarioError(fmt::format(
        "{}: key 'grid.cell_size': the scenario needs about {} of memory ({:.3g} material points, "
        "{:.3g} grid nodes) and this machine offers {}; coarsen the grid, lower "
        "particles_per_cell or shrink the bodies (or pass --force to try anyway)",
        s.source, gigabytes(z.memory_bytes), z.points, z.nodes, gigabytes(available)));
  // An implicit stage with the direct solver also holds the factor of its stiffness matrix.
  bool direct = false;
  for (const Stage& st : s.stages)
    direct = direct || (st.integrator == IntegratorKind::Implicit &&
                        st.implicit.linear_solver == LinearSolverKind::Direct);
  if (!direct) return;
  const ImplicitSystemSize k = estimate_implicit_system(s);
  if (z.memory_bytes + k.direct_bytes > 0.8 * available)
    throw ScenarioError(fmt::format(
        "{}: key 'implicit.linear_solver': the direct solver's factor of about {:.3g} unknowns needs "
        "about {} beside the points' {}, and this machine offers {}; set linear_solver = "
        "\"iterative\" (CG or GMRES with algebraic multigrid), or coarsen the grid (or pass --force to "
        "try anyway)",
        s.source, k.unknowns, gigabytes(k.direct_bytes), gigabytes(z.memory_bytes), gigabytes(available)));
}

template <int D>
void print_check(const ScenarioOf<D>& s, bool force) {
  const ScenarioSize z = estimate_size(s);
  if (!force) refuse_if_too_big(s, z);
  fmt::print("{}", describe(s));
  if (z.points <= kCountPointsUpTo)
    fmt::print("particles: {}\n", build_particles(s).size());
  else
    fmt::print("particles: about {:.3g} (estimated from the shapes)\n", z.points);
  if constexpr (D == 3)  // per layer from rasters: its volume and points
    for (const Body3& b : s.bodies)
      if (const auto* l = std::get_if<Layer3>(&b.shape)) {
        const double v = layer_volume(*l);
        fmt::print("layer {}: volume {:.6g} m^3, {}\n", b.name, v,
                   z.points <= kCountPointsUpTo
                       ? fmt::format("{} points", count_points(s, b))
                       : fmt::format("about {:.3g} points (from its volume)",
                                     v * std::pow(b.particles_per_cell / s.cell_size, 3)));
      }
  const double dt = scenario_time_step(s);
  double explicit_steps = 0.0;  // of the explicit stages (the implicit ones' steps are above)
  bool any_explicit = false;
  for (const Stage& st : s.stages)
    if (st.integrator == IntegratorKind::Explicit) {
      any_explicit = true;
      explicit_steps += std::ceil(st.duration / dt - 1e-9);
    }
  if (!any_explicit)
    fmt::print("time step: the implicit stages' own (above; the stable explicit step is {:.4g} s)\n",
               stable_time_step(s));
  else
    fmt::print("time step{}: {:.6g} s ({:.0f} steps; stable step {:.4g} s)\n",
               s.any_implicit() ? " of the explicit stages" : "", dt, explicit_steps, stable_time_step(s));
  if (any_explicit && dt > stable_time_step(s))
    fmt::print("warning: the time step exceeds the stable step (allow_unstable_time_step = true)\n");
  fmt::print("grid nodes: {:.0f}\nmemory: about {} (this machine offers {})\n", z.nodes,
             gigabytes(z.memory_bytes), gigabytes(available_memory_bytes()));
  fmt::print("output: {:.0f} particle frames of at most {:.3g} MB (less compressed), {} in all\n", z.frames,
             z.frame_bytes / 1e6, gigabytes(z.output_bytes()));
  if (z.points <= kCountPointsUpTo)
    fmt::print("{}", slope_stability_line(slope_stability(s)));  // 3D: a section
  fmt::print("scenario is valid\n");
}

int update_docs(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string updated = schema::update_generated_blocks(text.str());
  if (updated == text.str()) {
    fmt::print("{} is up to date\n", path);
    return 0;
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << updated;
  fmt::print("updated the generated key tables of {}\n", path);
  return 0;
}

}  // namespace

void require_fits_machine(const std::string& file) { require_fits_machine(load_any_scenario(file)); }

void require_fits_machine(const AnyScenario& s) {
  std::visit([](const auto& x) { refuse_if_too_big(x, estimate_size(x)); }, s);
}

ScenarioCommands::ScenarioCommands(CLI::App& app) {
  check_ = app.add_subcommand("check", "Validate a scenario and estimate its size without running it");
  check_->add_option("scenario", scenario_, "Scenario file (TOML)")->required()->check(CLI::ExistingFile);
  check_->add_flag("--force", force_, "Accept a scenario that needs more memory than the machine has");
  schema_ = app.add_subcommand("schema",
                               "Print every scenario key as markdown tables, or update "
                               "the generated tables of docs/scenario.md");
  schema_->add_option("--update", update_, "Rewrite the generated blocks of this markdown file");
}

int ScenarioCommands::run() const {
  if (*check_) {
    std::visit([&](const auto& s) { print_check(s, force_); }, load_any_scenario(scenario_));
    return 0;
  }
  if (!update_.empty()) return update_docs(update_);
  for (const schema::Section& s : schema::sections())
    fmt::print("## {}\n\n{}\n", s.name.empty() ? "top level" : s.name, schema::markdown_table(s));
  return 0;
}

}  // namespace skred
