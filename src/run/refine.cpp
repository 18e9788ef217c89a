#include "run/refine.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <set>
#include <stdexcept>
#include <variant>

#include "io/atomic_file.hpp"
#include "post/grid_convergence.hpp"
#include "run/extrapolation_text.hpp"
#include "run/simulation.hpp"
#include "run/table_text.hpp"
#include "scenario/scenario.hpp"

namespace skred {

namespace fs = std::filesystem;

namespace {

// Issue 12's bound on the runout's change per halving of the cell, and between transfers.
constexpr double kConverged = 0.05;

std::string num(double v) { return table_number(v); }

std::string label(const std::string& transfer) {
  return transfer.empty() ? std::string("scenario") : transfer;
}

// The change of the runout from the row before of the same transfer (NaN at its first level).
double change_at(const std::vector<RefineRow>& rows, std::size_t k) {
  if (k == 0 || rows[k].level == 0 || rows[k - 1].transfer != rows[k].transfer) return NAN;
  return relative_change(rows[k - 1].last.runout, rows[k].last.runout);
}

// A value of one measure: its unit and how to print it.
struct Measure {
  const char* name;   // the column of refine.csv
  const char* words;  // for the terminal
  const char* unit;   // with its leading space; "" for the gravity work (J, or J/m in 2D)
  double (*of)(const StageMeasures&);
};
constexpr Measure kMeasures[] = {
    {"runout", "runout", " m", [](const StageMeasures& m) { return m.runout; }},
    {"gravity_work", "gravity work (the energy released)", "",
     [](const StageMeasures& m) { return m.gravity_work; }},
};

}  // namespace

std::vector<RefineExtrapolation> refine_extrapolations(const std::vector<RefineRow>& rows) {
  std::vector<RefineExtrapolation> out;
  for (std::size_t k = 2; k < rows.size(); ++k) {
    const bool last_of_transfer = k + 1 == rows.size() || rows[k + 1].transfer != rows[k].transfer;
    if (!last_of_transfer || rows[k].level < 2 || rows[k - 2].transfer != rows[k].transfer) continue;
    const RefineRow *f = &rows[k], *m = &rows[k - 1], *c = &rows[k - 2];
    if (f->status != "completed" || m->status != "completed" || c->status != "completed") continue;
    for (const Measure& q : kMeasures) {
      RefineExtrapolation e;
      e.transfer = f->transfer;
      e.quantity = q.name;
      e.cell_size = f->cell_size;
      e.fine = q.of(f->last), e.medium = q.of(m->last), e.coarse = q.of(c->last);
      if (!std::isfinite(e.fine) || !std::isfinite(e.medium) || !std::isfinite(e.coarse)) continue;
      e.estimate = grid_convergence(e.fine, e.medium, e.coarse, m->cell_size / f->cell_size,
                                    c->cell_size / m->cell_size);
      out.push_back(e);
    }
  }
  return out;
}

std::string extrapolation_table(const std::vector<RefineExtrapolation>& ex) {
  std::string text =
      "transfer,quantity,cell_size,fine,medium,coarse,kind,ratio,order,extrapolated,approximate_error,"
      "extrapolated_error,gci_fine,next_change\n";
  auto out = std::back_inserter(text);
  for (const RefineExtrapolation& e : ex) {
    const GridConvergence& g = e.estimate;
    fmt::format_to(out, "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", label(e.transfer), e.quantity,
                   num(e.cell_size), num(e.fine), num(e.medium), num(e.coarse), convergence_kind_name(g.kind),
                   num(g.ratio), num(g.order), num(g.extrapolated), num(g.approximate_error),
                   num(g.extrapolated_error), num(g.gci_fine), num(g.next_change));
  }
  return text;
}

void check_refine_options(const RefineOptions& opt) {
  if (opt.levels < 2 || opt.levels > 5)
    throw std::invalid_argument(fmt::format("--levels must be 2 to 5 (h to h/16), got {}", opt.levels));
  std::set<std::string> seen;
  for (const std::string& t : opt.transfers)
    if (!seen.insert(t).second) throw std::invalid_argument("transfer '" + t + "' is given twice");
}

double relative_change(double a, double b) { return a > 0.0 ? (b - a) / a : NAN; }

std::vector<std::pair<std::string, double>> refined_keys(const AnyScenario& base, int level) {
  const ScenarioCommon& c = common_of(base);
  const int dim = std::holds_alternative<Scenario>(base) ? 2 : 3;
  const double f = std::ldexp(1.0, -level);  // 2^-k: exact, so the halved grids stay whole
  std::vector<std::pair<std::string, double>> set{{"grid.cell_size", c.cell_size * f}};
  if (c.time_step > 0.0) set.emplace_back("solver.time_step", c.time_step * f);  // c dt / h stays
  if (c.max_points_given)  // the cap grows with the points (10 x them if not given)
    set.emplace_back("splitting.max_points",
                     std::round(std::ldexp(static_cast<double>(c.splitting.max_points), dim * level)));
  return set;
}

std::vector<RefineRow> run_refine(const std::string& scenario_file, const fs::path& outdir,
                                  const RefineOptions& opt) {
  check_refine_options(opt);
  const std::string text = read_scenario_text(scenario_file);
  const AnyScenario base = parse_any_scenario(text, scenario_file);
  const double h = common_of(base).cell_size, dt = common_of(base).time_step;
  const std::vector<std::string> transfers =
      opt.transfers.empty() ? std::vector<std::string>{""} : opt.transfers;
  std::vector<RefineRow> rows;
  std::vector<AnyScenario> scenarios;  // every run validated before the first starts
  for (const std::string& t : transfers)
    for (int k = 0; k < opt.levels; ++k) {
      const double f = std::ldexp(1.0, -k);
      std::vector<std::pair<std::string, std::string>> text_set;
      if (!t.empty()) text_set.emplace_back("solver.velocity_transfer", t);
      scenarios.push_back(parse_any_scenario(text, scenario_file, refined_keys(base, k), text_set));
      if (opt.check) opt.check(scenarios.back());
      RefineRow r;
      r.transfer = t;
      r.level = k;
      r.cell_size = h * f;
      r.time_step = dt * f;
      r.folder = fmt::format("run_{:03}", rows.size());  // as a sweep's (run/output_folder.hpp)
      rows.push_back(r);
    }
  fs::create_directories(outdir);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    RefineRow& r = rows[i];
    if (opt.progress)
      fmt::print(stderr, "refine {}/{}: {}, cell size {} m\n", i + 1, rows.size(), label(r.transfer),
                 num(r.cell_size));
    RunOptions ro;
    ro.threads = opt.threads;
    ro.progress = opt.progress;
    const RunResult res = run_simulation(scenarios[i], outdir / r.folder, ro);
    r.status = run_status(res);
    r.particles = res.particles;
    r.wall_seconds = res.wall_seconds;
    if (!res.stages.empty()) r.last = res.stages.back();
    const std::vector<RefineRow> done(rows.begin(), rows.begin() + static_cast<long>(i) + 1);
    write_file_atomically(outdir / "refine.csv", [&](std::ostream& os) { os << refine_table(done); });
    write_file_atomically(outdir / "extrapolation.csv",
                          [&](std::ostream& os) { os << extrapolation_table(refine_extrapolations(done)); });
  }
  return rows;
}

std::string refine_table(const std::vector<RefineRow>& rows) {
  std::string text =
      "transfer,level,cell_size,time_step,particles,status,folder,wall_seconds,stage,ended_by,runout,"
      "runout_change,max_displacement,height_end,gravity_work,plastic_dissipation,final_mean_speed\n";
  auto out = std::back_inserter(text);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const RefineRow& r = rows[k];
    const StageMeasures& m = r.last;
    fmt::format_to(out, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", label(r.transfer), r.level,
                   num(r.cell_size), num(r.time_step), r.particles, r.status, r.folder, num(r.wall_seconds),
                   table_text(m.name), m.ended_by, num(m.runout), num(change_at(rows, k)),
                   num(m.max_displacement), num(m.height_end), num(m.gravity_work),
                   num(m.plastic_dissipation), num(m.final_mean_speed));
  }
  return text;
}

std::string refine_verdict(const std::vector<RefineRow>& rows) {
  std::string text = fmt::format("{:>10} {:>10} {:>11} {:>9} {:>14} {:>10}\n", "transfer", "h [m]",
                                 "runout [m]", "change", "gravity work", "ended by");
  auto out = std::back_inserter(text);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const RefineRow& r = rows[k];
    const double c = change_at(rows, k);
    fmt::format_to(out, "{:>10} {:>10.4g} {:>11.4f} {:>9} {:>14.6g} {:>10}\n", label(r.transfer), r.cell_size,
                   r.last.runout, std::isfinite(c) ? fmt::format("{:+.1f} %", 100.0 * c) : std::string("-"),
                   r.last.gravity_work, r.status == "completed" ? r.last.ended_by : r.status);
  }
  std::vector<const RefineRow*> finest;  // the last level of each transfer
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (k + 1 < rows.size() && rows[k + 1].transfer == rows[k].transfer) continue;
    finest.push_back(&rows[k]);
    const double c = change_at(rows, k);
    if (!std::isfinite(c)) {
      fmt::format_to(out, "{}: no change of the runout to report (one level, or no runout at the coarser)\n",
                     label(rows[k].transfer));
      continue;
    }
    fmt::format_to(
        out, "{}: the last halving (h = {} to {} m) moved the runout by {:+.2f} %: {}\n",
        label(rows[k].transfer), num(rows[k - 1].cell_size), num(rows[k].cell_size), 100.0 * c,
        std::abs(c) < kConverged ? "within 5 %" : "NOT within 5 %; refine further before relying on it");
  }
  const std::vector<RefineExtrapolation> ex = refine_extrapolations(rows);
  if (!ex.empty())
    fmt::format_to(out,
                   "Richardson's extrapolation of the last three sizes (Celik et al. 2008; "
                   "extrapolation.csv):\n");
  for (const RefineExtrapolation& e : ex) {
    const Measure& m = e.quantity == "runout" ? kMeasures[0] : kMeasures[1];
    const ThreeGrids v{{e.cell_size, 2.0 * e.cell_size, 4.0 * e.cell_size}, {e.fine, e.medium, e.coarse}};
    fmt::format_to(out, "{}: {}", label(e.transfer),
                   extrapolation_line(m.words, m.unit, v, e.estimate, " m"));
  }
  if (finest.size() > 1) {
    double lo = INFINITY, hi = -INFINITY;
    for (const RefineRow* r : finest) lo = std::min(lo, r->last.runout), hi = std::max(hi, r->last.runout);
    const double spread = relative_change(lo, hi);
    if (!std::isfinite(spread))
      fmt::format_to(out, "at h = {} m a transfer gives no runout to compare\n",
                     num(finest.front()->cell_size));
    else
      fmt::format_to(
          out, "at h = {} m the transfers' runouts lie within {:.2f} % of each other: {}\n",
          num(finest.front()->cell_size), 100.0 * spread,
          spread < kConverged ? "within 5 %" : "NOT within 5 %: the runout depends on the velocity transfer");
    double elo = INFINITY, ehi = -INFINITY;
    int extrapolated = 0;
    for (const RefineExtrapolation& e : ex)
      if (e.quantity == "runout" && std::isfinite(e.estimate.extrapolated))
        ++extrapolated, elo = std::min(elo, e.estimate.extrapolated),
                        ehi = std::max(ehi, e.estimate.extrapolated);
    if (extrapolated == static_cast<int>(finest.size()) && std::isfinite(relative_change(elo, ehi)))
      fmt::format_to(out, "as h -> 0 the transfers' extrapolated runouts lie within {:.2f} % of each other\n",
                     100.0 * relative_change(elo, ehi));
  }
  return text;
}

}  // namespace skred
