// The command line of a run (issue 13): exit codes as README documents them (a death by
// signal never counts as a clean rejection), --version, refusing an output folder that holds
// an earlier run unless --overwrite, a killed run, an unstable time step, and the OpenMP wait
// policy skred sets unless the user set one.
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "temp_dir.hpp"

namespace fs = std::filesystem;
using skred::test::TempDir;

namespace {

struct Outcome {
  int code = -1;       // exit code, or -1 when killed by a signal
  int signal = 0;      // the signal that ended it, if any
  std::string output;  // stdout and stderr
};

Outcome sh(const std::string& command) {
  Outcome r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0;) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  if (status != -1 && WIFEXITED(status)) r.code = WEXITSTATUS(status);
  if (status != -1 && WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

std::string q(const fs::path& p) {
  std::string s = "'";
  for (char c : p.string()) s += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return s + "'";
}

const std::string kSkred = q(SKRED_BINARY);

std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& f, const std::string& text) { std::ofstream(f) << text; }

// The colliding discs example with a replaced line.
std::string discs(const std::string& from, const std::string& to) {
  std::string t = read(fs::path(SKRED_SOURCE_DIR) / "examples" / "colliding_discs.toml");
  const auto at = t.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? t : t.replace(at, from.size(), to);
}

// A short run: the discs until 0.2 s (200 steps, 3 frames).
std::string short_discs() { return discs("end_time = 3.0", "end_time = 0.2"); }

}  // namespace

TEST(CliRun, VersionNamesTheReleaseAndTheCommit) {
  const Outcome r = sh(kSkred + " --version");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(
      std::regex_search(r.output, std::regex(R"(^skred \d+\.\d+\.\d+ \(commit ([0-9a-f]{40}|unknown)\))")))
      << r.output;
}

TEST(CliRun, UsageErrorsExitWithCode4) {
  for (const char* args :
       {"", " run", " frobnicate", " run x.toml", " bench --threads 0", " bench --problem block --dim 3",
        " bench --problem column --bodies 2 --velocity-transfer aflip"}) {
    SCOPED_TRACE(args);
    const Outcome r = sh(kSkred + args);
    EXPECT_EQ(r.signal, 0);
    EXPECT_EQ(r.code, 4) << r.output;
    EXPECT_FALSE(r.output.empty());
  }
}

// Under an MPI launcher (mpirun -np N) every one of the N copies would run the whole scenario
// into the same folder: each refuses, naming the launcher's count, and writes nothing.
// Under an MPI launcher `run` and `bench` split among its processes (parallel/processes.hpp);
// the commands that run in one process refuse, rather than have N copies write one folder.
TEST(CliRun, RunsAcrossTheProcessesOfAnMpiLauncher) {
  TempDir d;
  write(d / "discs.toml", short_discs());
  for (const std::string env : {"OMPI_COMM_WORLD_SIZE=2", "PMI_SIZE=4"}) {
    SCOPED_TRACE(env);
    const Outcome r = sh(env + " " + kSkred + " sweep " + q(d / "discs.toml") +
                         " --set 'material[0].density=1000:2000:2' -o " + q(d / "sweep"));
    EXPECT_EQ(r.code, 4) << r.output;
    EXPECT_NE(r.output.find("one of " + env.substr(env.find('=') + 1) + " processes"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(d / "sweep"));
  }
  const std::string mpirun = "OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np 2 ";
  // `skred run`: one folder, one report, the frames in pieces.
  const Outcome run =
      sh(mpirun + kSkred + " run " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1");
  EXPECT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("completed"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("completed"), run.output.rfind("completed"))
      << "one process reports: " << run.output;
  EXPECT_TRUE(fs::exists(d / "out" / "particles_000000.pvtu"));
  EXPECT_TRUE(fs::exists(d / "out" / "particles_000000" / "piece_0001.vtu"));
  EXPECT_NE(read(d / "out" / "summary.json").find("\"processes\": {\"count\": 2,"), std::string::npos);
  // A failure stops every process, each naming itself: no checkpoint to resume from.
  const Outcome bad = sh(mpirun + kSkred + " resume " + q(d / "out"));
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("skred: process "), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("checkpoint"), std::string::npos) << bad.output;
  // `skred bench`: the first process prints the figures of both.
  const Outcome bench =
      sh(mpirun + kSkred + " bench --problem block --particles 1000 --steps 2 --repeats 1 --threads 1");
  EXPECT_EQ(bench.code, 0) << bench.output;
  EXPECT_NE(bench.output.find("2 processes x 1 thread(s)"), std::string::npos) << bench.output;
  EXPECT_EQ(bench.output.find("median:"), bench.output.rfind("median:"))
      << "one process prints: " << bench.output;
  // One process (mpirun -np 1) runs as without the launcher.
  const Outcome one =
      sh("OMPI_COMM_WORLD_SIZE=1 " + kSkred + " run " + q(d / "discs.toml") + " -o " + q(d / "one"));
  EXPECT_EQ(one.code, 0) << one.output;
  EXPECT_TRUE(fs::exists(d / "one" / "particles_000000.vtu"));
}

TEST(CliRun, InvalidScenarioExitsWithCode5NamingTheKey) {
  TempDir d;
  write(d / "bad.toml", discs("density = 1000.0", "density = \"heavy\""));
  for (const std::string& args :
       {" check " + q(d / "bad.toml"), " run " + q(d / "bad.toml") + " -o " + q(d / "out")}) {
    const Outcome r = sh(kSkred + args);
    EXPECT_EQ(r.code, 5) << r.output;
    EXPECT_NE(r.output.find("bad.toml:13:11: key 'material[0].density'"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
}

// summary.json's peak memory: above the idle process, per point, so bytes_per_point x points
// stays below the whole peak (the idle process is not counted) and above the points' own
// arrays (x, x_ref, v, half0, F, stress, state, mass, volume0: at least 150 bytes in 2D).
TEST(CliRun, SummaryReportsThePeakMemoryPerPoint) {
  TempDir d;
  write(d / "discs.toml", short_discs());
  ASSERT_EQ(sh(kSkred + " run " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1").code, 0);
  const std::string summary = read(d / "out" / "summary.json");
  std::smatch peak, per_point, points;
  ASSERT_TRUE(std::regex_search(summary, peak, std::regex(R"("peak_bytes": ([0-9.e+]+))"))) << summary;
  ASSERT_TRUE(std::regex_search(summary, per_point, std::regex(R"("bytes_per_point": ([0-9.e+]+))")))
      << summary;
  ASSERT_TRUE(std::regex_search(summary, points, std::regex(R"("particles": (\d+))"))) << summary;
  const double n = std::stod(points[1]);
  ASSERT_GT(n, 0.0);
  EXPECT_LT(std::stod(per_point[1]) * n, std::stod(peak[1]));
  EXPECT_GT(std::stod(per_point[1]), 150.0);
}

TEST(CliRun, AnOutputFolderHoldingARunIsRefusedUnlessOverwrite) {
  TempDir d;
  write(d / "discs.toml", short_discs());
  const std::string run = kSkred + " run " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1";
  ASSERT_EQ(sh(run).code, 0);
  const std::string summary = read(d / "out" / "summary.json");
  write(d / "out" / "particles_000099.vtu", "stale frame of an older, longer run");
  write(d / "out" / "notes.txt", "the user's own file");

  const Outcome again = sh(run);
  EXPECT_EQ(again.code, 1) << again.output;
  EXPECT_NE(again.output.find("holds an earlier run"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("--overwrite"), std::string::npos) << again.output;
  EXPECT_EQ(read(d / "out" / "summary.json"), summary);  // untouched
  EXPECT_TRUE(fs::exists(d / "out" / "particles_000099.vtu"));

  const Outcome over = sh(run + " --overwrite");
  EXPECT_EQ(over.code, 0) << over.output;
  EXPECT_FALSE(fs::exists(d / "out" / "particles_000099.vtu"));  // no stale frame beside the new
  EXPECT_TRUE(fs::exists(d / "out" / "particles_000002.vtu"));
  EXPECT_EQ(read(d / "out" / "notes.txt"), "the user's own file");  // only skred's files go

  // The scenario file itself may live in the folder: --overwrite keeps it.
  fs::copy_file(d / "discs.toml", d / "out" / "scenario.toml", fs::copy_options::overwrite_existing);
  const Outcome inside = sh(kSkred + " run " + q(d / "out" / "scenario.toml") + " -o " + q(d / "out") +
                            " --threads 1 --overwrite");
  EXPECT_EQ(inside.code, 0) << inside.output;
  EXPECT_EQ(read(d / "out" / "scenario.toml"), short_discs());
}

TEST(CliRun, ASweepFolderIsRefusedUnlessOverwrite) {
  TempDir d;
  write(d / "discs.toml", discs("end_time = 3.0", "end_time = 0.05"));
  const std::string sweep = kSkred + " sweep " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1";
  ASSERT_EQ(sh(sweep + " --set 'material[elastic].young=1000,2000'").code, 0);
  const Outcome again = sh(sweep + " --set 'material[elastic].young=1000'");
  EXPECT_EQ(again.code, 1) << again.output;
  EXPECT_NE(again.output.find("holds an earlier run"), std::string::npos) << again.output;
  const Outcome over = sh(sweep + " --set 'material[elastic].young=1000' --overwrite");
  EXPECT_EQ(over.code, 0) << over.output;
  EXPECT_TRUE(fs::exists(d / "out" / "run_000" / "summary.json"));
  EXPECT_FALSE(fs::exists(d / "out" / "run_001"));  // the earlier sweep's second run is gone
}

// `skred refine`: the scenario at h and h/2 per transfer, the verdict on stdout and refine.csv;
// its folder is refused on a second study unless --overwrite; bad levels are a usage error.
TEST(CliRun, ARefinementStudyTellsHowFarTheRunoutMoved) {
  TempDir d;
  write(d / "discs.toml", discs("end_time = 3.0", "end_time = 0.02"));
  const std::string refine =
      kSkred + " refine " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1";
  const Outcome r = sh(refine + " --levels 2 --transfers flip,apic");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("flip: the last halving (h = "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the transfers' runouts"), std::string::npos) << r.output;
  EXPECT_EQ(read(d / "out" / "refine.csv").rfind("transfer,level,cell_size,", 0), 0u);
  EXPECT_TRUE(fs::exists(d / "out" / "run_003" / "summary.json"));
  EXPECT_EQ(sh(refine + " --levels 2").code, 1);
  EXPECT_EQ(sh(refine + " --levels 2 --overwrite").code, 0);
  EXPECT_FALSE(fs::exists(d / "out" / "run_002"));  // the earlier study's apic runs are gone
  const Outcome bad = sh(refine + " --levels 1 --overwrite");
  EXPECT_EQ(bad.code, 4) << bad.output;
  EXPECT_NE(bad.output.find("--levels must be 2 to 5"), std::string::npos) << bad.output;
  // Three levels: Richardson's extrapolation of the runout and the gravity work, and its table.
  const Outcome three = sh(refine + " --levels 3 --overwrite");
  ASSERT_EQ(three.code, 0) << three.output;
  EXPECT_NE(three.output.find("Richardson's extrapolation of the last three sizes"), std::string::npos)
      << three.output;
  const std::string ex = read(d / "out" / "extrapolation.csv");
  EXPECT_EQ(ex.rfind("transfer,quantity,cell_size,fine,medium,coarse,kind,", 0), 0u) << ex;
  EXPECT_EQ(std::count(ex.begin(), ex.end(), '\n'), 3) << ex;  // the header, runout, gravity work
}

// `skred fos`: the 50 m slope at 5 and 2.5 m cells (--levels 2), a 5 s gravity ramp and a 10 s
// slide (the example's 12.5 and 80 s, shortened for time), stands at f = 0.5
// and fails at 0.7 (within 1.3 s; Bishop's F 0.587 on the 5 m cells; test_strength_reduction.cpp
// bisects it); the verdict, fos.csv and the picture.
TEST(CliRun, AFactorOfSafetyStudyBracketsTheOnset) {
  TempDir d;
  std::string text = read(fs::path(SKRED_SOURCE_DIR) / "examples" / "slope_50m.toml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"cell_size = 2.5", "cell_size = 5.0"},
        {"duration = 80.0", "duration = 10.0"},
        {"duration = 15.0\ngravity_ramp_time = 12.5", "duration = 6.0\ngravity_ramp_time = 5.0"}}) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  }
  write(d / "slope.toml", text);
  const std::string fos = kSkred + " fos " + q(d / "slope.toml") + " -o " + q(d / "out") + " --threads 1";
  const Outcome r = sh(fos + " --range 0.5 0.7 --steps 0 --levels 2");  // at 5 and 2.5 m cells
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* at : {"at h = 5 m", "at h = 2.5 m"})
    EXPECT_NE(r.output.find(std::string(at) + " the MPM's factor of safety lies between 0.5 and 0.7"),
              std::string::npos)
        << r.output;
  EXPECT_NE(r.output.find("limit equilibrium (Bishop's simplified method on circles): F = 0.58"),
            std::string::npos)
      << r.output;
  const std::string table = read(d / "out" / "fos.csv");
  EXPECT_EQ(table.rfind("factor,status,folder,fails,max_displacement,height_start,threshold,", 0), 0u)
      << table;
  EXPECT_NE(table.find("\n0.7,completed,run_001,true,"), std::string::npos) << table;
  EXPECT_NE(table.find(",1,2.5\n"), std::string::npos) << table;  // level 1, h/2
  EXPECT_TRUE(fs::exists(d / "out" / "run_003" / "summary.json"));
  EXPECT_TRUE(fs::exists(d / "out" / "pictures" / "fos.png"));
  EXPECT_EQ(sh(fos + " --range 0.5 0.7 --steps 0").code, 1);  // an earlier study, not --overwrite
  const Outcome bad = sh(fos + " --range 0.7 0.5 --overwrite");
  EXPECT_EQ(bad.code, 4) << bad.output;
  EXPECT_NE(bad.output.find("--range needs 0 < LOW < HIGH"), std::string::npos) << bad.output;
  EXPECT_EQ(sh(fos + " --levels 5 --overwrite").code, 4);
}

TEST(CliRun, AKilledRunLeavesCompleteFilesAndIsNotReusedSilently) {
  TempDir d;
  std::string text = discs("cell_size = 0.05", "cell_size = 0.02");  // 30,000 steps: several seconds
  text.replace(text.find("end_time = 3.0"), 14, "end_time = 30.0");
  write(d / "discs.toml", text);
  const std::string run = kSkred + " run " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1";
  // SIGKILL 0.5 s after the first frame is indexed, not after a fixed time, which a slow build
  // (scripts/sanitize.sh) may spend before its first frame.
  const Outcome killed =
      sh("{ " + run + " & pid=$!; while [ ! -e " + q(d / "out" / "particles.pvd") +
         " ] && kill -0 $pid 2>/dev/null; do sleep 0.05; done; sleep 0.5; kill -KILL $pid; "
         "wait $pid; }");
  ASSERT_EQ(killed.code, 137) << "the run must take longer than its first frame and 0.5 s: " << killed.output;
  ASSERT_TRUE(fs::exists(d / "out" / "particles.pvd"));
  // Every frame the index names is complete (files are renamed into place when written).
  const std::string pvd = read(d / "out" / "particles.pvd");
  ASSERT_NE(pvd.find("</VTKFile>"), std::string::npos);
  int frames = 0;
  const std::regex file_re(R"(file="([^"]+)\")");
  for (std::sregex_iterator m(pvd.begin(), pvd.end(), file_re), e; m != e; ++m, ++frames) {
    const std::string vtu = read(d / "out" / (*m)[1].str());
    EXPECT_NE(vtu.rfind("</VTKFile>\n"), std::string::npos) << (*m)[1].str();
  }
  EXPECT_GE(frames, 1);
  const Outcome again = sh(run);
  EXPECT_EQ(again.code, 1) << again.output;
  EXPECT_NE(again.output.find("holds an earlier run"), std::string::npos) << again.output;
}

// c dt / h = 1.5 and 2.2 (c: P-wave speed): refused as an invalid scenario before anything
// runs, naming the key and the stable step. A user who insists (allow_unstable_time_step)
// gets a run the detector stops as "unstable", never one that ends "completed".
TEST(CliRun, ATimeStepAboveTheStableLimitEndsUnstable) {
  TempDir d;
  const double c = std::sqrt(1000.0 * 0.7 / (1.3 * 0.4) / 1000.0), h = 0.05;
  for (double courant : {1.5, 2.2}) {
    SCOPED_TRACE(courant);
    const std::string step = "time_step = " + std::to_string(courant * h / c);
    const fs::path file = d / ("discs_" + std::to_string(courant) + ".toml");
    write(file, discs("time_step = 0.001", step));
    const fs::path out = d / ("out_" + std::to_string(courant));
    const Outcome r = sh(kSkred + " run " + q(file) + " -o " + q(out) + " --threads 1");
    EXPECT_EQ(r.code, 5) << r.output;
    EXPECT_NE(r.output.find("key 'solver.time_step'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("exceeds the stable time step"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out / "summary.json"));
    if (courant < 2) continue;
    write(file, discs("time_step = 0.001", step + "\nallow_unstable_time_step = true"));
    const Outcome forced = sh(kSkred + " run " + q(file) + " -o " + q(out) + " --threads 1");
    EXPECT_EQ(forced.code, 2) << forced.output;
    EXPECT_NE(forced.output.find("unstable"), std::string::npos) << forced.output;
    EXPECT_NE(read(out / "summary.json").find("\"status\": \"unstable\""), std::string::npos);
  }
}

TEST(CliRun, SummaryNamesTheVersionAndCommit) {
  TempDir d;
  write(d / "discs.toml", short_discs());
  ASSERT_EQ(sh(kSkred + " run " + q(d / "discs.toml") + " -o " + q(d / "out") + " --threads 1").code, 0);
  const std::string version = sh(kSkred + " --version").output;
  const std::string summary = read(d / "out" / "summary.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(version, m, std::regex(R"(skred (\S+) \(commit (\S+)\))")));
  EXPECT_NE(summary.find("\"version\": \"" + m[1].str() + "\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"git_commit\": \"" + m[2].str() + "\""), std::string::npos) << summary;
}

namespace {

// libgomp reports the settings it took (OMP_DISPLAY_ENV, printed as it loads); the last
// report is the process that runs.
std::string last_spin(const std::string& out) {
  std::string last;
  const std::regex spin_re(R"(GOMP_SPINCOUNT = '(\d+)')");
  for (std::sregex_iterator m(out.begin(), out.end(), spin_re), e; m != e; ++m) last = (*m)[1].str();
  return last;
}

const std::string kNoWaitSettings = "env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT -u SKRED_OMP_WAIT ";

}  // namespace

// One thread never waits at a barrier: the short spin, whatever the load.
TEST(CliRun, ShortSpinWaitForOneThreadTheUsersOwnSettingOtherwise) {
  const std::string base = kNoWaitSettings + "OMP_DISPLAY_ENV=verbose ";
  const Outcome def = sh(base + "OMP_NUM_THREADS=1 " + kSkred + " --version");
  EXPECT_EQ(def.code, 0);
  EXPECT_EQ(last_spin(def.output), "1000") << def.output;
  const Outcome user = sh(base + "GOMP_SPINCOUNT=300000 " + kSkred + " --version");
  EXPECT_EQ(last_spin(user.output), "300000") << user.output;
  const Outcome active = sh(base + "OMP_WAIT_POLICY=active " + kSkred + " --version");
  EXPECT_NE(active.output.find("OMP_WAIT_POLICY = 'ACTIVE'"), std::string::npos) << active.output;
  EXPECT_NE(last_spin(active.output), "1000") << active.output;
  const std::string bench = " bench --problem block --particles 1000 --steps 1 --repeats 1 --threads 2";
  const Outcome told = sh(kNoWaitSettings + "GOMP_SPINCOUNT=5 " + kSkred + bench);
  EXPECT_NE(told.output.find("OpenMP wait: spin 5 (GOMP_SPINCOUNT set by the user)"), std::string::npos)
      << told.output;
}

// Two threads beside a process computing on every CPU this one may use: the short spin (more
// load elsewhere only makes the machine busier, so this holds on any machine). Without them,
// the spin libgomp took is the one the bench reports, the short or the long.
TEST(CliRun, TwoThreadsOnABusyMachineWaitWithTheShortSpin) {
  cpu_set_t mine;
  ASSERT_EQ(sched_getaffinity(0, sizeof mine, &mine), 0);
  if (CPU_COUNT(&mine) < 2) GTEST_SKIP() << "one CPU: two threads always take the short spin";
  const std::string bench = kNoWaitSettings + "OMP_DISPLAY_ENV=verbose " + kSkred +
                            " bench --problem block --particles 1000 --steps 1 --repeats 1 --threads 2";
  const Outcome any = sh(bench);
  ASSERT_EQ(any.code, 0) << any.output;
  const std::string spin = last_spin(any.output);
  EXPECT_TRUE(spin == "1000" || spin == "10000") << any.output;
  EXPECT_NE(any.output.find("OpenMP wait: spin " + spin + " ("), std::string::npos) << any.output;

  std::string hogs, pids;  // one `yes` per CPU, for 20 s at most
  for (int i = 0; i < CPU_COUNT(&mine); ++i) {
    hogs += "timeout 20 yes > /dev/null & p" + std::to_string(i) + "=$!; ";
    pids += " $p" + std::to_string(i);
  }
  const Outcome busy = sh("(" + hogs + "sleep 0.3; " + bench + "; kill" + pids + " 2> /dev/null; true)");
  EXPECT_EQ(last_spin(busy.output), "1000") << busy.output;
  EXPECT_NE(busy.output.find("OpenMP wait: spin 1000 (other processes"), std::string::npos) << busy.output;
}

// With binding asked for (OMP_PROC_BIND), the re-execution that sets the spin keeps it:
// libgomp (OMP_DISPLAY_AFFINITY) binds the two threads of a run to two different CPUs, as it
// does without the re-execution, where before they both landed on the CPU libgomp had bound
// the first image's initial thread to.
TEST(CliRun, ThreadBindingSurvivesTheSpinReexecution) {
  cpu_set_t mine;
  ASSERT_EQ(sched_getaffinity(0, sizeof mine, &mine), 0);
  if (CPU_COUNT(&mine) < 2) GTEST_SKIP() << "one CPU: two threads cannot be bound apart";
  const std::string run =
      kSkred + " bench --problem block --particles 1000 --steps 1 --repeats 1 --threads 2";
  for (const char* bind : {"close", "spread"}) {
    const Outcome r = sh(kNoWaitSettings + "-u OMP_PLACES OMP_PROC_BIND=" + bind +
                         " OMP_DISPLAY_ENV=verbose OMP_DISPLAY_AFFINITY=true " + run);
    ASSERT_EQ(r.code, 0) << r.output;
    const std::string spin = last_spin(r.output);
    EXPECT_TRUE(spin == "1000" || spin == "10000") << r.output;  // re-executed
    std::vector<std::string> cpus;
    const std::regex aff_re(R"(level 1 thread \S+ affinity (\S+))");
    for (std::sregex_iterator m(r.output.begin(), r.output.end(), aff_re), e; m != e; ++m)
      cpus.push_back((*m)[1].str());
    ASSERT_EQ(cpus.size(), 2u) << r.output;
    EXPECT_NE(cpus[0], cpus[1]) << bind << ": both threads bound to CPU " << cpus[0] << "\n" << r.output;
  }
}

// `skred sweep` over a 2 x 2 grid (repeated --set): one row per run with both keys' values,
// the first key varying slowest, clean numbers, and the picture pictures/sweep.png.
TEST(CliRun, ASweepOverAGridWritesOneRowPerRunAndAPicture) {
  TempDir d;
  write(d / "discs.toml", discs("end_time = 3.0", "end_time = 0.02"));
  const Outcome r = sh(kSkred + " sweep " + q(d / "discs.toml") + " -o " + q(d / "out") +
                       " --threads 1 --set 'material[elastic].young=1000,2000'"
                       " --set 'material[elastic].poisson=0.1:0.2:0.1'");
  ASSERT_EQ(r.code, 0) << r.output;
  std::istringstream table(read(d / "out" / "sweep.csv"));
  std::string header, line;
  std::getline(table, header);
  EXPECT_EQ(header.rfind("material[elastic].young,material[elastic].poisson,status,folder,", 0), 0u)
      << header;
  for (const char* m :
       {",max_displacement,", ",runout,", ",peak_mean_speed,", ",stop_time,", ",plastic_volume,"})
    EXPECT_NE(header.find(m), std::string::npos) << m;
  std::vector<std::string> rows;
  while (std::getline(table, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);
  const char* expected[] = {"1000,0.1,completed,run_000,", "1000,0.2,completed,run_001,",
                            "2000,0.1,completed,run_002,", "2000,0.2,completed,run_003,"};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(rows[k].rfind(expected[k], 0), 0u) << rows[k];
    // 12 significant digits at most: no rounding noise such as 0.020000000000000004.
    EXPECT_FALSE(std::regex_search(rows[k], std::regex(R"([1-9]\d{12})"))) << rows[k];
    EXPECT_TRUE(fs::exists(d / "out" / ("run_00" + std::to_string(k)) / "summary.json"));
  }
  const fs::path png = d / "out" / "pictures" / "sweep.png";
  ASSERT_TRUE(fs::exists(png)) << r.output;
  const Outcome check =
      sh("/usr/bin/python3 -c 'import sys; from PIL import Image; im = Image.open(sys.argv[1]); im.load(); "
         "print(im.format, im.size[0] >= 400 and im.size[1] >= 300)' " +
         q(png));
  EXPECT_EQ(check.output, "PNG True\n");
}

// A malformed --set is a usage error (exit code 4) that quotes the bad part; nothing runs.
TEST(CliRun, ABadSweepSetIsAUsageError) {
  TempDir d;
  write(d / "discs.toml", short_discs());
  const std::string sweep = kSkred + " sweep " + q(d / "discs.toml") + " -o " + q(d / "out") + " --set ";
  const std::pair<const char*, const char*> cases[] = {
      {"'material[elastic].young'", "expected KEY=V1,V2,... or KEY=FROM:TO:STEP"},
      {"'material[elastic].young=1000,abc'", "'abc' is not a number"},
      {"'material[elastic].young=2000:1000:100'", "must be a number or FROM:TO:STEP"},
      {"'material[elastic].young=1000' --set 'material[elastic].young=2000'", "is swept twice"},
  };
  for (const auto& [set, message] : cases) {
    SCOPED_TRACE(set);
    const Outcome r = sh(sweep + set);
    EXPECT_EQ(r.signal, 0);
    EXPECT_EQ(r.code, 4) << r.output;  // README, "Exit codes": usage
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "out" / "run_000"));
  }
}

// Without Python the runs still complete and sweep.csv is written; the exit code says the
// picture is missing (6, README "Exit codes") and the message what to install.
TEST(CliRun, ASweepWithoutPythonKeepsItsTable) {
  TempDir d;
  write(d / "discs.toml", discs("end_time = 3.0", "end_time = 0.02"));
  const Outcome r = sh("SKRED_PYTHON=/nonexistent/python3 " + kSkred + " sweep " + q(d / "discs.toml") +
                       " -o " + q(d / "out") + " --threads 1 --set 'material[elastic].young=1000'");
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.code, 6) << r.output;
  EXPECT_NE(r.output.find("apt-get install python3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sweep.csv is complete"), std::string::npos) << r.output;
  EXPECT_NE(read(d / "out" / "sweep.csv").find("\n1000,completed,run_000,"), std::string::npos);
}

// `skred check` sets a slope against limit equilibrium before any run (run/slope_stability.hpp):
// Bishop's factor, the circle and what it means, or why it was not computed.
TEST(CliRun, CheckGivesASlopesLimitEquilibrium) {
  const std::string examples = q(fs::path(SKRED_SOURCE_DIR) / "examples");
  const Outcome slope = sh(kSkred + " check " + examples + "/slope_collapse.toml");
  EXPECT_EQ(slope.code, 0) << slope.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      slope.output, m, std::regex(R"(limit equilibrium \(Bishop's simplified method.*F = ([0-9.]+) on)")))
      << slope.output;
  EXPECT_NEAR(std::stod(m[1].str()), 0.82, 0.01);  // docs/method.md, "Limit equilibrium"
  EXPECT_NE(slope.output.find("sliding towards +x: the slope is not expected to stand: its soil has 82 % of "
                              "the strength it needs"),
            std::string::npos);
  // Layered ground (clay on sand) with a contact between the layers, which the circles ignore.
  const Outcome layered = sh(kSkred + " check " + examples + "/rubjerg_knude.toml");
  EXPECT_NE(layered.output.find("dry, the strengths of sand, clay in stage 'rain'): F = "), std::string::npos)
      << layered.output;
  EXPECT_NE(
      layered.output.find("note: the contact between 'sand' and 'clay' (mu = 0.6) is not a weakness to it"),
      std::string::npos)
      << layered.output;
  const Outcome elastic = sh(kSkred + " check " + examples + "/elastic_column.toml");
  EXPECT_NE(elastic.output.find("limit equilibrium: not computed (material 'soil' does not yield)"),
            std::string::npos)
      << elastic.output;
}

// Under an address-space limit (ulimit -v) a scenario that cannot fit is refused by its size,
// naming the key, before it starts (fuzzing: such a run ended in a bare std::bad_alloc; one that
// passes the estimate and still runs out now says "out of memory" with what was left, main.cpp).
// The soil column at 2 cm cells: 1.1e6 points, about 0.66 GB.
TEST(CliRun, AnAddressSpaceLimitIsRead) {
  TempDir d;
  std::string t = read(fs::path(SKRED_SOURCE_DIR) / "examples" / "soil_column.toml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"cell_size = 0.5", "cell_size = 0.02"},
                                 {"time_step = 0.001", "cfl = 0.5"}}) {
    const auto at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
  }
  write(d / "fine.toml", t);
  const Outcome small =
      sh("ulimit -v 600000; " + kSkred + " run " + q(d / "fine.toml") + " -o " + q(d / "out"));
  EXPECT_EQ(small.code, 5) << small.output;
  EXPECT_NE(small.output.find("key 'grid.cell_size': the scenario needs about"), std::string::npos)
      << small.output;
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
}

// A scenario of 10^6 points or more says what its set-up is doing before the time loop starts
// (fuzzing: 10^7 points filled for 34 s in silence). The soil column at 2 cm cells, 1.12e6
// points, for two steps.
TEST(CliRun, ALargeSetUpReportsItsProgress) {
  TempDir d;
  std::string t = read(fs::path(SKRED_SOURCE_DIR) / "examples" / "soil_column.toml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"cell_size = 0.5", "cell_size = 0.02"},
                                 {"time_step = 0.001", "cfl = 0.5"},
                                 {"duration = 6.0", "duration = 5e-5"}}) {
    const auto at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
  }
  write(d / "fine.toml", t);
  const Outcome r = sh(kSkred + " run " + q(d / "fine.toml") + " -o " + q(d / "out") + " --threads 2");
  EXPECT_EQ(r.code, 0) << r.output;
  const auto filling = r.output.find("set-up: filling the bodies with about 1.12e+06 points (");
  const auto stress = r.output.find("set-up: the initial stress (");
  const auto frame = r.output.find("set-up: the first frame (");
  const auto done = r.output.find("set-up: done; the time loop starts (");
  EXPECT_NE(filling, std::string::npos) << r.output;
  EXPECT_LT(filling, stress);
  EXPECT_LT(stress, frame);
  EXPECT_LT(frame, done);
  EXPECT_NE(done, std::string::npos) << r.output;
}
