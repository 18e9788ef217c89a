#include "run/checkpointing.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "io/atomic_file.hpp"
#include "parallel/point_shares.hpp"
#include "scenario/initial_stress.hpp"

namespace skred {

namespace fs = std::filesystem;

namespace {

// Set by the SIGINT/SIGTERM handler, read between steps. A second signal before the run
// stops ends the program at once (the default action).
volatile std::sig_atomic_t g_stop_requested = 0;
extern "C" void request_stop(int sig) {
  if (g_stop_requested) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
  g_stop_requested = 1;
}
bool g_watching = false;  // watch_stop_signals() was called

template <class A>
void archive_row(A& a, SeriesRow& r) {
  a(r.step);
  a(r.time);
  a(r.kinetic_energy);
  a(r.strain_energy);
  a(r.gravity_work);
  a(r.plastic_dissipation);
  a(r.friction_work);
  a(r.transfer_dissipation);
  a(r.mean_speed);
  a(r.max_speed);
  a(r.momentum_x);
  a(r.momentum_y);
  a(r.num_particles);
  a(r.stage);
  a(r.runout);
  a(r.yielding_points);
  a(r.momentum_z);
  a(r.contact_work);
  a(r.damping_work);
  a(r.material_speed);
  a(r.iterations);
  a(r.residual);
  a(r.load_work);
  for (double& f : r.boundary_force) a(f);
}

// The run's state besides the particles, in payload order.
template <class A, int D>
void archive_run(A& a, SolverClock& c, RunProgress<D>& at) {
  a(c.time);
  a(c.steps);
  a(c.ramp_start);
  a(c.gravity_ramp_time);
  a(c.energy.strain_energy);
  a(c.energy.gravity_work);
  a(c.energy.plastic_dissipation);
  a(c.energy.contact_work);
  a(c.energy.friction_work);
  a(c.energy.transfer_dissipation);
  a(c.energy.damping_work);
  a(c.energy.load_work);
  for (double& f : c.boundary_force) a(f);
  a(at.stage);
  a(at.in_stage);
  a(at.stage_first_step);
  a(at.stage_start);
  a(at.next_output);
  a(at.next_series);
  a(at.frame_times);
  a(at.checkpoint_every);
  std::uint64_t n = at.finished.size();
  a(n);
  at.finished.resize(n);
  for (StageMeasures& m : at.finished) archive_measures(a, m);
  if (at.in_stage) at.tracker.archive(a);
  at.maps.archive(a);
  a(at.map_files);
}

}  // namespace

void watch_stop_signals() {
  g_watching = true;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

fs::path checkpoint_file(const fs::path& outdir) { return outdir / "checkpoint.skc"; }

fs::path checkpoint_piece(const fs::path& outdir, int rank, int processes) {
  return outdir / fmt::format("checkpoint.{}-of-{}.skc", rank, processes);
}

fs::path checkpoint_manifest(const fs::path& outdir) { return outdir / "checkpoint.manifest"; }

std::uint64_t scenario_hash(const std::string& source) {
  std::ifstream in(source, std::ios::binary);
  std::string text = source;
  if (in && fs::is_regular_file(source))
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return fnv1a64(text.data(), text.size());
}

template <int D>
Checkpointing<D>::Checkpointing(const ScenarioOf<D>& s, const fs::path& outdir, const RunOptions& opt)
    : s_(s),
      procs_(opt.processes),
      outdir_(outdir),
      file_(procs_.distributed() ? checkpoint_piece(outdir, procs_.rank(), procs_.size())
                                 : checkpoint_file(outdir)),
      restart_(opt.restart),
      every_(opt.checkpoint_every),
      stop_at_(opt.stop_at_step),
      signals_(opt.handle_signals) {
  if (!signals_) return;
  if (!g_watching) g_stop_requested = 0;  // a signal since watch_stop_signals() still counts
  struct sigaction sa {};
  sa.sa_handler = request_stop;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int_);
  sigaction(SIGTERM, &sa, &old_term_);
}

template <int D>
Checkpointing<D>::~Checkpointing() {
  if (!signals_) return;
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

template <int D>
void Checkpointing<D>::write(const Particles<D>& P, const Integrator<D>& solver, RunProgress<D>& at,
                             const SeriesWriter& series) {
  std::ostringstream os(std::ios::binary);
  ByteWriter w{os};
  SolverClock c = solver.clock();
  at.checkpoint_every = every_;
  archive_run(w, c, at);
  w(static_cast<std::uint64_t>(series.rows().size()));
  for (SeriesRow r : series.rows()) archive_row(w, r);
  P.serialise(os);
  write_checkpoint(file_, {D, scenario_hash(s_.source)}, os.str());
  std::error_code ec;
  if (!procs_.distributed()) {
    fs::remove(checkpoint_manifest(outdir_), ec);  // (an older checkpoint in pieces)
    return;
  }
  std::vector<double> points(static_cast<std::size_t>(procs_.size()));
  const double mine = static_cast<double>(P.size());
  procs_.gather(&mine, 1, points.data(), points.size());
  procs_.barrier();  // every piece is on disk before the manifest names them
  if (procs_.rank() != 0) return;
  write_file_atomically(checkpoint_manifest(outdir_), [&](std::ostream& m) {
    m << "skred checkpoint in pieces\nprocesses " << procs_.size() << "\nstep " << c.steps << "\npoints";
    for (double k : points) m << ' ' << static_cast<long>(k);
    m << '\n';
  });
  fs::remove(checkpoint_file(outdir_), ec);
}

std::vector<PieceRun> pieces_to_read(const std::vector<long>& points, int rank, int processes) {
  long m = 0;
  for (long k : points) m += k;
  const auto cut = [&](long q) { return static_cast<long>(static_cast<__int128>(m) * q / processes); };
  const long lo = cut(rank), hi = cut(rank + 1);
  std::vector<PieceRun> runs;
  long start = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const long end = start + points[k], a = std::max(lo, start), b = std::min(hi, end);
    if (a < b) runs.push_back({static_cast<long>(k), a - start, b - start});
    start = end;
  }
  if (runs.empty() && !points.empty()) {  // (an empty share: the piece where it would begin)
    long piece = 0;
    for (start = 0; piece + 1 < static_cast<long>(points.size()) &&
                    start + points[static_cast<std::size_t>(piece)] <= lo;
         ++piece)
      start += points[static_cast<std::size_t>(piece)];
    runs.push_back({piece, 0, 0});
  }
  return runs;
}

// The pieces of the checkpoint `manifest` names (Checkpointing::restore).
template <int D>
void Checkpointing<D>::load_pieces(const fs::path& manifest, Particles<D>& P, SolverClock& c,
                                   RunProgress<D>& at, std::vector<SeriesRow>& rows) const {
  std::ifstream in(manifest);
  std::string head, key_n, key_step;
  long n = 0, step = -1;
  std::getline(in, head);
  if (!(head == "skred checkpoint in pieces" && in >> key_n >> n >> key_step >> step &&
        key_n == "processes" && key_step == "step" && n >= 1 && n <= 1000000))
    throw CheckpointError(fmt::format("checkpoint manifest '{}' is not one skred wrote", manifest.string()));
  const auto piece = [&](long r, Particles<D>& into) {
    const fs::path file = checkpoint_piece(manifest.parent_path(), static_cast<int>(r), static_cast<int>(n));
    load_checkpoint(file, s_, into, c, at, rows);
    if (c.steps != step)
      throw CheckpointError(fmt::format("checkpoint piece '{}' is of step {}, its manifest '{}' of step {}",
                                        file.string(), c.steps, manifest.string(), step));
  };
  if (n == procs_.size()) {  // the same split: this process's own points
    piece(procs_.rank(), P);
    return;
  }
  std::string key_points;
  std::vector<long> points;
  if (in >> key_points) {  // (a manifest of 2026-12-06 or before has no counts)
    points.resize(static_cast<std::size_t>(n));
    for (long& k : points)
      if (!(key_points == "points" && in >> k && k >= 0))
        throw CheckpointError(fmt::format(
            "checkpoint manifest '{}': its 'points' line is not one skred wrote", manifest.string()));
  }
  P = Particles<D>();
  if (points.empty()) {  // every piece, keeping this process's share of each
    for (long r = 0; r < n; ++r) {
      Particles<D> part;
      piece(r, part);
      keep_share(part, procs_);
      P.append(part);
    }
    return;
  }
  // Another count: the pieces that hold this process's share, each read whole and the share
  // kept, so a process holds its share and one piece at most; the run's first step cuts the blocks.
  for (const PieceRun& run : pieces_to_read(points, procs_.rank(), procs_.size())) {
    Particles<D> part;
    piece(run.piece, part);
    if (static_cast<long>(part.size()) != points[static_cast<std::size_t>(run.piece)])
      throw CheckpointError(fmt::format(
          "checkpoint piece '{}' holds {} points, its manifest '{}' says {}",
          checkpoint_piece(manifest.parent_path(), static_cast<int>(run.piece), static_cast<int>(n)).string(),
          part.size(), manifest.string(), points[static_cast<std::size_t>(run.piece)]));
    std::vector<std::uint8_t> keep(part.size(), 0);
    std::fill(keep.begin() + run.first, keep.begin() + run.end, std::uint8_t{1});
    part.erase(keep);
    P.append(part);
  }
}

template <int D>
void load_checkpoint(const fs::path& file, const ScenarioOf<D>& s, Particles<D>& P, SolverClock& c,
                     RunProgress<D>& at, std::vector<SeriesRow>& series) {
  std::istringstream is(read_checkpoint(file, {D, scenario_hash(s.source)}), std::ios::binary);
  ByteReader r{is, fmt::format("checkpoint '{}'", file.string())};
  archive_run(r, c, at);
  std::uint64_t rows = 0;
  r(rows);
  r.need(rows < (1ull << 32));
  series.resize(rows);
  for (SeriesRow& row : series) archive_row(r, row);
  try {
    P.deserialise(is);
  } catch (const std::runtime_error& e) {
    throw CheckpointError(fmt::format("checkpoint '{}': {}", file.string(), e.what()));
  }
  r.need(is.peek() == std::char_traits<char>::eof() && at.stage <= s.stages.size() &&
         (at.stage < s.stages.size() || !at.in_stage));
}

template <int D>
bool Checkpointing<D>::restore(Particles<D>& P, Integrator<D>& solver, RunProgress<D>& at,
                               SeriesWriter& series, PvdWriter& particles_pvd, PvdWriter& grid_pvd) {
  if (restart_.empty()) return false;
  SolverClock c;
  std::vector<SeriesRow> rows;
  if (const fs::path manifest = checkpoint_manifest(restart_.parent_path());
      restart_.filename() == checkpoint_file("").filename() && fs::exists(manifest)) {
    load_pieces(manifest, P, c, at, rows);
  } else {
    load_checkpoint(restart_, s_, P, c, at, rows);
    keep_share(P, procs_);
  }
  if (every_ == 0) every_ = at.checkpoint_every;  // a resume keeps the run's period
  for (const SeriesRow& row : rows) series.add(row);
  const std::size_t stage = std::min<std::size_t>(at.stage, s_.stages.size() - 1);
  solver.restore(c, stage_materials(s_, s_.stages[stage]));
  for (std::size_t f = 0; f < at.frame_times.size(); ++f) {  // .pvtu: a frame in pieces
    const std::string in_pieces = fmt::format("particles_{:06}.pvtu", f);
    particles_pvd.add(at.frame_times[f],
                      fs::exists(outdir_ / in_pieces) ? in_pieces : fmt::format("particles_{:06}.vtu", f));
    grid_pvd.add(at.frame_times[f], fmt::format("grid_{:06}.vtr", f));
  }
  return true;
}

template <int D>
bool Checkpointing<D>::after_step(const Particles<D>& P, const Integrator<D>& solver, RunProgress<D>& at,
                                  const SeriesWriter& series) {
  if (procs_.any(g_stop_requested || solver.steps() == stop_at_)) {
    write(P, solver, at, series);
    return true;
  }
  if (every_ > 0 && solver.steps() % every_ == 0) write(P, solver, at, series);
  return false;
}

template <int D>
void Checkpointing<D>::at_end(const Particles<D>& P, const Integrator<D>& solver, RunProgress<D>& at,
                              const SeriesWriter& series) {
  if (every_ > 0) write(P, solver, at, series);
}

template class Checkpointing<2>;
template class Checkpointing<3>;
template void load_checkpoint(const fs::path&, const ScenarioOf<2>&, Particles<2>&, SolverClock&,
                              RunProgress<2>&, std::vector<SeriesRow>&);
template void load_checkpoint(const fs::path&, const ScenarioOf<3>&, Particles<3>&, SolverClock&,
                              RunProgress<3>&, std::vector<SeriesRow>&);

}  // namespace skred
