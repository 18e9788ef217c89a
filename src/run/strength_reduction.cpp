#include "run/strength_reduction.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "run/refine.hpp"
#include "run/simulation.hpp"
#include "run/slope_stability.hpp"
#include "run/table_text.hpp"
#include "scenario/initial_stress.hpp"

namespace skred {

namespace fs = std::filesystem;

namespace {

// The last stage that lets the soil yield (as slope_stability takes its strength).
std::size_t slide_stage(const ScenarioCommon& s, const std::string& file) {
  for (std::size_t k = s.stages.size(); k-- > 0;)
    if (!s.stages[k].elastic) {
      for (const Material& m : stage_materials(s, s.stages[k]))
        if (m.plastic()) return k;
      break;
    }
  throw ScenarioError(file +
                      ": no material can yield in the last stage that is not held elastic; strength "
                      "reduction needs a stage that lets the soil yield");
}

}  // namespace

void check_fos_options(const FosOptions& opt) {
  if (!(opt.low > 0.0 && opt.low < opt.high))
    throw std::invalid_argument(fmt::format("--range needs 0 < LOW < HIGH, got {} {}", opt.low, opt.high));
  if (opt.steps < 0 || opt.steps > 12)
    throw std::invalid_argument(fmt::format("--steps must be 0 to 12, got {}", opt.steps));
  if (!(opt.moved > 0.0 && opt.moved < 1.0))
    throw std::invalid_argument(fmt::format("--moved must lie between 0 and 1, got {}", opt.moved));
  if (opt.levels < 1 || opt.levels > 4)
    throw std::invalid_argument(fmt::format("--levels must be 1 to 4 (h to h/8), got {}", opt.levels));
}

std::optional<GridConvergence> fos_extrapolation(const FosResult& r) {
  const std::size_t n = r.levels.size();
  if (n < 3) return std::nullopt;
  const FosLevel *f = &r.levels[n - 1], *m = &r.levels[n - 2], *c = &r.levels[n - 3];
  for (const FosLevel* l : {f, m, c})
    if (!std::isfinite(l->stands) || !std::isfinite(l->fails)) return std::nullopt;
  return grid_convergence(f->midpoint(), m->midpoint(), c->midpoint(), m->cell_size / f->cell_size,
                          c->cell_size / m->cell_size);
}

FosResult run_strength_reduction(const std::string& scenario_file, const fs::path& outdir,
                                 const FosOptions& opt) {
  check_fos_options(opt);
  const std::string text = read_scenario_text(scenario_file);
  const AnyScenario base = parse_any_scenario(text, scenario_file);
  const std::size_t k = slide_stage(common_of(base), scenario_file);
  if (text.find("[[stage]]") == std::string::npos)
    throw ScenarioError(scenario_file +
                        ": strength reduction sets a [[stage]]'s strength_reduction, and the scenario has no "
                        "[[stage]] table: add one (e.g. an elastic equilibrium stage, then the slide)");
  const double own = common_of(base).stages[k].strength_reduction;
  const std::string key = fmt::format("stage[{}].strength_reduction", k);
  const auto scenario_at = [&](double f, int level) {
    std::vector<std::pair<std::string, double>> set = refined_keys(base, level);
    set.emplace_back(key, own * f);
    AnyScenario s = parse_any_scenario(text, scenario_file, set);
    // The slide runs its whole duration: a slope near its onset starts slowly, and the rest test
    // (mean speed below rest_speed for rest_time) would end it as standing before it fails.
    common_of(s).stages[k].rest_speed = 0.0;
    if (opt.check) opt.check(s);
    return s;
  };
  for (int l = 0; l < opt.levels; ++l)  // every level's ends valid (and fitting) before the first run
    scenario_at(opt.low, l), scenario_at(opt.high, l);

  FosResult result;
  result.stage = common_of(base).stages[k].name;
  if (const Scenario* s2 = std::get_if<Scenario>(&base))
    if (const SlopeStability le = slope_stability(*s2); le.computed)
      result.limit_equilibrium = le.critical.factor;
  fs::create_directories(outdir);
  const auto run = [&](double f, int level) {
    FosRun r;
    r.factor = f;
    r.level = level;
    r.cell_size = common_of(base).cell_size * std::ldexp(1.0, -level);
    r.folder = fmt::format("run_{:03}", result.runs.size());  // as a sweep's (run/output_folder.hpp)
    if (opt.progress)
      fmt::print(stderr, "fos {}: stage '{}' with the strength divided by {}, cell size {} m\n",
                 result.runs.size() + 1, result.stage, table_number(f), table_number(r.cell_size));
    RunOptions ro;
    ro.threads = opt.threads;
    ro.progress = opt.progress;
    ro.stop_stage = static_cast<int>(k), ro.stop_moved = opt.moved;  // failed: no need to run on
    const RunResult res = run_simulation(scenario_at(f, level), outdir / r.folder, ro);
    r.status = run_status(res);
    const bool reached = res.stages.size() > k;  // the slide stage ran (to its end or not)
    if (reached) r.stage = res.stages[k];
    // A run that left the grid or went unstable in the slide counts as failing.
    r.threshold = opt.moved * r.stage.height_start;
    r.fails = !res.completed || !reached || r.stage.max_displacement > r.threshold;
    result.runs.push_back(r);
    write_file_atomically(outdir / "fos.csv", [&](std::ostream& os) { os << fos_table(result); });
    return r.fails;
  };
  for (int l = 0; l < opt.levels; ++l) {
    FosLevel level;
    level.cell_size = common_of(base).cell_size * std::ldexp(1.0, -l);
    level.fails_at_low = run(opt.low, l);
    if (!level.fails_at_low && run(opt.high, l)) {  // else the ends do not bracket the onset
      double stands = opt.low, fails = opt.high;
      for (int i = 0; i < opt.steps; ++i) {
        const double mid = 0.5 * (stands + fails);
        (run(mid, l) ? fails : stands) = mid;
      }
      level.stands = stands, level.fails = fails;
    }
    result.levels.push_back(level);
  }
  result.stands = result.levels.back().stands, result.fails = result.levels.back().fails;
  return result;
}

std::string fos_table(const FosResult& result) {
  std::string text =
      "factor,status,folder,fails,max_displacement,height_start,threshold,runout,ended_by,stage_time,"
      "gravity_work,plastic_dissipation,limit_equilibrium,level,cell_size\n";
  auto out = std::back_inserter(text);
  for (const FosRun& r : result.runs) {
    const StageMeasures& m = r.stage;
    fmt::format_to(out, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", table_number(r.factor), r.status,
                   r.folder, r.fails ? "true" : "false", table_number(m.max_displacement),
                   table_number(m.height_start), table_number(r.threshold), table_number(m.runout),
                   table_text(m.ended_by), table_number(m.end_time - m.start_time),
                   table_number(m.gravity_work), table_number(m.plastic_dissipation),
                   table_number(result.limit_equilibrium), r.level, table_number(r.cell_size));
  }
  return text;
}

std::string fos_verdict(const FosResult& r, const FosOptions& opt) {
  std::string text = fmt::format(
      "strength reduction of stage '{}' (c, tan(phi) and tan(psi) divided by f; fails: a point moved more "
      "than "
      "{} % of the material's height within the stage):\n",
      table_text(r.stage), table_number(100.0 * opt.moved));
  auto out = std::back_inserter(text);
  const bool several = r.levels.size() > 1;
  for (const FosRun& run : r.runs)
    fmt::format_to(out, "  {}f = {}: {} (largest displacement {:.3g} m, the height {:.3g} m){}\n",
                   several ? fmt::format("h = {} m, ", table_number(run.cell_size)) : std::string(),
                   table_number(run.factor), run.fails ? "fails" : "stands", run.stage.max_displacement,
                   run.stage.height_start, run.status == "completed" ? "" : ", " + run.status);
  for (const FosLevel& l : r.levels) {
    const std::string at = several ? fmt::format("at h = {} m ", table_number(l.cell_size)) : std::string();
    if (std::isfinite(l.stands))
      fmt::format_to(out, "{}the MPM's factor of safety lies between {} and {}\n", at, table_number(l.stands),
                     table_number(l.fails));
    else if (l.fails_at_low)
      fmt::format_to(
          out, "{}the slope fails already at f = {}: its factor of safety is below it (lower --range)\n", at,
          table_number(opt.low));
    else
      fmt::format_to(out, "{}the slope stands at f = {}: its factor of safety is above it (raise --range)\n",
                     at, table_number(opt.high));
  }
  if (const std::optional<GridConvergence> g = fos_extrapolation(r)) {
    const std::size_t n = r.levels.size();
    const double width = r.levels[n - 1].fails - r.levels[n - 1].stands;
    const double last = r.levels[n - 1].midpoint() - r.levels[n - 2].midpoint();
    fmt::format_to(out, "Richardson's extrapolation of the brackets' midpoints (Celik et al. 2008): ");
    if (std::isfinite(g->extrapolated) && g->kind != ConvergenceKind::diverging)
      fmt::format_to(
          out,
          "{} with apparent order p = {:.2f}, towards f = {:.3f} as h -> 0 (GCI of the finest {:.1f} %)\n",
          g->kind == ConvergenceKind::oscillatory ? "it oscillates (extrapolate with care)"
                                                  : "it converges monotonically",
          g->order, g->extrapolated, 100.0 * g->gci_fine);
    else
      fmt::format_to(out, "{}: nothing is extrapolated\n",
                     g->kind == ConvergenceKind::diverging
                         ? "the last change is not smaller than the one before"
                         : "no apparent order");
    if (std::abs(last) < width)
      fmt::format_to(
          out,
          "  the finest bracket ({} wide) is wider than the last change of its midpoint ({:+.4f}): the "
          "extrapolation rests on the bisection's resolution; raise --steps\n",
          table_number(width), last);
  }
  if (std::isfinite(r.limit_equilibrium))
    fmt::format_to(out, "limit equilibrium (Bishop's simplified method on circles): F = {:.3f}\n",
                   r.limit_equilibrium);
  return text;
}

}  // namespace skred
