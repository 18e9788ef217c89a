// Checkpoint and restart (run/checkpointing.hpp, io/checkpoint.hpp): a run stopped at a
// checkpoint and restarted ends bit for bit where the uninterrupted run ends, for every
// scheme, with two bodies and a stage boundary between the checkpoint and the end; files that
// cannot be used are rejected naming the file and what is wrong.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/checkpoint.hpp"
#include "run/checkpointing.hpp"
#include "run/simulation.hpp"
#include "temp_dir.hpp"

using namespace skred;
namespace fs = std::filesystem;

namespace {

// Two soil columns of different materials side by side; stage 1 ramps gravity in (held
// elastic), stage 2 lets them collapse as Mohr-Coulomb.
std::string two_body_text(const char* scheme) {
  return std::string(R"(
[grid]
size = [0.4, 0.2]
cell_size = 0.02
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 1800.0
young = 1e6
poisson = 0.3
friction = 25.0
cohesion = 100.0
[[material]]
name = "clay"
model = "mohr-coulomb"
density = 1600.0
young = 2e6
poisson = 0.25
friction = 15.0
cohesion = 400.0
[[body]]
name = "left"
material = "sand"
shape = "rectangle"
min = [0.0, 0.0]
max = [0.1, 0.12]
[[body]]
name = "right"
material = "clay"
shape = "rectangle"
min = [0.1, 0.0]
max = [0.2, 0.1]
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
y_min = "fixed"
[solver]
cfl = 0.3
scheme = ")") +
         scheme + R"("
[[stage]]
name = "gravity"
duration = 0.04
gravity_ramp_time = 0.03
elastic = true
[[stage]]
name = "collapse"
duration = 0.05
[output]
interval = 0.01
series_interval = 0.002
)";
}

std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& f, const std::string& text) {
  std::ofstream out(f, std::ios::binary);
  out << text;
}

// Bitwise equality of two arrays of one field (PointState member by member: no padding).
template <class T>
bool bits_equal(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return false;
  if constexpr (std::is_same_v<T, PointState>) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (std::memcmp(&a[i].plastic_shear_strain, &b[i].plastic_shear_strain, 3 * sizeof(double)) ||
          a[i].yielding != b[i].yielding)
        return false;
    return true;
  } else {
    return a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
  }
}

struct Loaded {
  Particles<2> P;
  SolverClock clock;
  RunProgress<2> at;
  std::vector<SeriesRow> series;
};
Loaded load(const fs::path& file, const Scenario& s) {
  Loaded l;
  load_checkpoint(file, s, l.P, l.clock, l.at, l.series);
  return l;
}

// Runs a shell command; its exit code and its output (stdout and stderr).
std::pair<int, std::string> shell(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  char buf[4096];
  for (std::size_t n; pipe && (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  const int status = pipe ? pclose(pipe) : -1;
  return {status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

fs::path fresh_dir(const std::string& name) { return skred::test::fresh_temp_dir(name); }

}  // namespace

TEST(Checkpoint, RestartReproducesTheUninterruptedRunBitForBit) {
  // (the fourth and fifth: with the cell-averaged volumetric strain, whose cell sums are not state)
  const std::pair<const char*, const char*> runs[] = {
      {"usf", "usf"},
      {"usl", "usl"},
      {"averaged", "averaged"},
      {"usf-cell-average", "usf\"\nvolumetric_strain = \"cell-average"},
      {"averaged-cell-average", "averaged\"\nvolumetric_strain = \"cell-average"},
      // XPIC once per 2.5 h/c (every 8 or 9 steps): the filter steps come from the time alone
      {"usf-periodic-xpic",
       "usf\"\nvelocity_transfer = \"xpic\"\nxpic_period = 2.5\ninterpolation = \"gimp"}};
  for (const auto& [name, scheme] : runs) {
    SCOPED_TRACE(name);
    const fs::path dir = fresh_dir(name);
    write(dir / "two_bodies.toml", two_body_text(scheme));
    const Scenario s = load_scenario((dir / "two_bodies.toml").string());
    RunOptions opt;
    opt.progress = false;
    opt.threads = std::string(scheme) == "averaged" ? 2 : 1;  // the same count when restarted
    opt.checkpoint_every = 1000000;                           // only the final one
    const RunResult a = run_simulation(s, dir / "a", opt);
    ASSERT_TRUE(a.completed) << a.message;
    ASSERT_EQ(a.stages.size(), 2u);

    RunOptions stop = opt;  // stops mid-stage-1, as on SIGINT, at a step where points sort next
    stop.stop_at_step = 100;
    const RunResult b = run_simulation(s, dir / "b", stop);
    ASSERT_TRUE(b.interrupted);
    ASSERT_LT(b.simulated_time, 0.04);
    EXPECT_NE(read(dir / "b" / "summary.json").find("\"status\": \"interrupted\""), std::string::npos);
    const Loaded mid = load(dir / "b" / "checkpoint.skc", s);
    EXPECT_EQ(mid.clock.steps, 100);
    EXPECT_EQ(mid.at.stage, 0u);
    EXPECT_TRUE(mid.at.in_stage);

    RunOptions again = opt;
    again.restart = dir / "b" / "checkpoint.skc";
    const RunResult c = run_simulation(s, dir / "b", again);
    ASSERT_TRUE(c.completed) << c.message;
    EXPECT_EQ(c.steps, a.steps);

    const Loaded A = load(dir / "a" / "checkpoint.skc", s), B = load(dir / "b" / "checkpoint.skc", s);
    EXPECT_EQ(A.at.stage, 2u);
    A.P.for_each_field([&](const auto& f, const auto& fa) {
      const auto& fb = B.P.*(f.member);
      EXPECT_TRUE(bits_equal(fa, fb)) << "field " << f.name;
    });
    EXPECT_EQ(std::memcmp(&A.clock, &B.clock, sizeof(SolverClock)), 0);  // time, steps, energies
    EXPECT_EQ(read(dir / "a" / "series.csv"), read(dir / "b" / "series.csv"));
    EXPECT_EQ(read(dir / "a" / "particles.pvd"), read(dir / "b" / "particles.pvd"));
    for (int f = 0; f < 12; ++f) {
      const std::string name = (f < 10 ? "particles_00000" : "particles_0000") + std::to_string(f) + ".vtu";
      ASSERT_FALSE(read(dir / "a" / name).empty()) << name;
      EXPECT_EQ(read(dir / "a" / name), read(dir / "b" / name)) << name;
    }
    ASSERT_EQ(c.stages.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(a.stages[k].runout, c.stages[k].runout);
      EXPECT_EQ(a.stages[k].gravity_work, c.stages[k].gravity_work);
      EXPECT_EQ(a.stages[k].strain_energy, c.stages[k].strain_energy);
      EXPECT_EQ(a.stages[k].plastic_dissipation, c.stages[k].plastic_dissipation);
      EXPECT_EQ(a.stages[k].plastic_volume, c.stages[k].plastic_volume);
      EXPECT_EQ(a.stages[k].peak_mean_speed, c.stages[k].peak_mean_speed);
    }
    EXPECT_GT(a.stages[1].plastic_points, 0);  // the collapse is plastic
    fs::remove_all(dir);
  }
}

TEST(Checkpoint, UnusableFilesAreRejectedNamingTheFile) {
  const fs::path dir = fresh_dir("corrupt");
  write(dir / "run.toml", two_body_text("usf"));
  const Scenario s = load_scenario((dir / "run.toml").string());
  RunOptions opt;
  opt.progress = false;
  opt.stop_at_step = 20;
  ASSERT_TRUE(run_simulation(s, dir / "out", opt).interrupted);
  const std::string good = read(dir / "out" / "checkpoint.skc");
  EXPECT_NO_THROW(load(dir / "out" / "checkpoint.skc", s));

  auto rejects = [&](const std::string& bytes, const std::string& what, const Scenario& sc) {
    const fs::path f = dir / "bad.skc";
    write(f, bytes);
    RunOptions r;
    r.progress = false;
    r.restart = f;
    try {
      run_simulation(sc, dir / "again", r);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const CheckpointError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(f.string()), std::string::npos) << m;
      EXPECT_NE(m.find(what), std::string::npos) << m;
    }
  };
  std::string flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;
  rejects(flipped, "corrupt (checksum mismatch)", s);
  rejects(good.substr(0, good.size() - 100), "truncated", s);
  rejects(good.substr(0, 20), "truncated", s);
  rejects(read(dir / "run.toml"), "not a skred checkpoint", s);
  std::string v2 = good;
  const std::uint32_t version = kCheckpointVersion + 1;
  std::memcpy(v2.data() + 8, &version, 4);
  const std::uint64_t sum = fnv1a64(v2.data(), v2.size() - 8);
  std::memcpy(v2.data() + v2.size() - 8, &sum, 8);
  rejects(v2, "format version " + std::to_string(kCheckpointVersion + 1), s);
  write(dir / "other.toml", two_body_text("usl"));
  rejects(good, "another scenario", load_scenario((dir / "other.toml").string()));
  fs::remove_all(dir);
}

// The command line: SIGINT stops `skred run` with a checkpoint, status "interrupted" and exit
// code 3; `skred resume OUTDIR` and `skred run --restart FILE` finish the run with the same
// series; a foreign file given to --restart is an error naming it.
TEST(Checkpoint, CommandLineInterruptResumeAndRestart) {
  const fs::path dir = fresh_dir("cli");
  std::string text = read(fs::path(SKRED_SOURCE_DIR) / "examples" / "colliding_discs.toml");
  text.replace(text.find("cell_size = 0.05"), 16, "cell_size = 0.02");  // 3,000 steps, ~2 s
  for (int k = 0; k < 2; ++k) text.replace(text.find("particles_per_cell = 2"), 22, "particles_per_cell = 3");
  write(dir / "discs.toml", text);
  const std::string skred = SKRED_BINARY, scen = (dir / "discs.toml").string();
  const std::string out = (dir / "out").string(), out2 = (dir / "out2").string();
  // SIGINT once the run has begun (series.csv is opened before the first step, the handler
  // installed before the scenario is read), 0.3 s in: not after a fixed time, which a slow
  // build (scripts/sanitize.sh) may spend starting up.
  const auto [code, msg] = shell("{ " + skred + " run " + scen + " -o " + out +
                                 " --threads 1 --checkpoint-every 500 & pid=$!; while [ ! -e " + out +
                                 "/series.csv ] && kill -0 $pid 2>/dev/null; do sleep 0.05; done; "
                                 "sleep 0.3; kill -INT $pid; wait $pid; }");
  ASSERT_EQ(code, 3) << msg;  // needs the run to take longer than 0.3 s
  EXPECT_NE(msg.find("skred resume " + out), std::string::npos) << msg;
  EXPECT_NE(read(dir / "out" / "summary.json").find("\"status\": \"interrupted\""), std::string::npos);
  fs::copy_file(dir / "out" / "checkpoint.skc", dir / "stopped.skc");
  const std::string stopped = read(dir / "out" / "summary.json");
  const std::size_t at = stopped.find("\"steps\": ");
  ASSERT_NE(at, std::string::npos) << stopped;
  const long stopped_step = std::stol(stopped.substr(at + 9));
  const auto [resumed, rmsg] = shell(skred + " resume " + out + " --threads 1");
  EXPECT_EQ(resumed, 0) << rmsg;
  EXPECT_NE(read(dir / "out" / "summary.json").find("\"status\": \"completed\""), std::string::npos);
  EXPECT_NE(read(dir / "out" / "summary.json").find("\"steps\": 3000"), std::string::npos);
  const auto [restarted, smsg] = shell(skred + " run " + scen + " -o " + out2 + " --threads 1 --restart " +
                                       (dir / "stopped.skc").string());
  EXPECT_EQ(restarted, 0) << smsg;
  EXPECT_EQ(read(dir / "out" / "series.csv"), read(dir / "out2" / "series.csv"));
  // --restart may name a checkpoint in pieces by its manifest (here one piece, as one process of
  // `mpirun -np 1` writes it).
  fs::create_directories(dir / "pieces");
  fs::copy_file(dir / "stopped.skc", checkpoint_piece(dir / "pieces", 0, 1));
  write(checkpoint_manifest(dir / "pieces"),
        "skred checkpoint in pieces\nprocesses 1\nstep " + std::to_string(stopped_step) + "\n");
  const auto [manifest, mmsg] =
      shell(skred + " run " + scen + " -o " + (dir / "out3").string() + " --threads 1 --restart " +
            checkpoint_manifest(dir / "pieces").string());
  EXPECT_EQ(manifest, 0) << mmsg;
  EXPECT_EQ(read(dir / "out" / "series.csv"), read(dir / "out3" / "series.csv"));
  const auto [foreign, fmsg] = shell(skred + " run " + scen + " -o " + out2 + " --restart " + scen);
  EXPECT_EQ(foreign, 1);
  EXPECT_NE(fmsg.find(scen + "' is not a skred checkpoint"), std::string::npos) << fmsg;
  fs::remove_all(dir);
}

// A checkpoint in pieces resumed on another count (issue 55): each process reads only the pieces
// that hold its share [m r / N, m (r + 1) / N) of the m points, and together the processes take
// every point once, in the pieces' order; a process with an empty share reads one piece.
TEST(Checkpoint, PiecesToReadOnAnotherCount) {
  const std::vector<long> points = {5, 0, 7, 3, 0, 9};
  const long m = 24;
  for (int N : {1, 2, 3, 5, 7, 24, 40}) {
    long next = 0;  // the next point, over the pieces, that some process must take
    for (int r = 0; r < N; ++r) {
      const std::vector<PieceRun> runs = pieces_to_read(points, r, N);
      ASSERT_FALSE(runs.empty()) << N << " processes, rank " << r;
      long share = 0, read_points = 0;
      for (const PieceRun& run : runs) {
        ASSERT_GE(run.piece, 0);
        ASSERT_LT(run.piece, static_cast<long>(points.size()));
        const long p = points[static_cast<std::size_t>(run.piece)];
        ASSERT_LE(0, run.first);
        ASSERT_LE(run.first, run.end);
        ASSERT_LE(run.end, p);
        long start = 0;
        for (long k = 0; k < run.piece; ++k) start += points[static_cast<std::size_t>(k)];
        if (run.end > run.first) {
          EXPECT_EQ(start + run.first, next)
              << N << " processes, rank " << r << ": a point skipped or taken twice";
          next = start + run.end;
        }
        share += run.end - run.first;
        read_points += p;
      }
      EXPECT_EQ(share, m * (r + 1) / N - m * r / N) << N << " processes, rank " << r;
      // It reads no piece beyond those its share touches: at most its share and two pieces' points.
      EXPECT_LE(read_points, share + 2 * 9) << N << " processes, rank " << r;
      if (share == 0) {
        EXPECT_EQ(runs.size(), 1u);
      }
    }
    EXPECT_EQ(next, m) << N << " processes: not every point was taken";
  }
  EXPECT_TRUE(pieces_to_read({}, 0, 2).empty());  // (no pieces: nothing to read)
}
