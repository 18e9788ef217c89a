// Result files besides the VTU: atomic writing, the PVD index, series.csv and summary.json.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/pvd_writer.hpp"
#include "io/series_writer.hpp"
#include "io/summary_writer.hpp"
#include "io_test_util.hpp"

using namespace skred;
using namespace skred::iotest;
namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& file, const std::string& text) {
  write_file_atomically(file, [&](std::ostream& os) { os << text; });
}

// Expects `call` to throw std::runtime_error whose message names `file`.
template <class F>
void expect_error_naming(const fs::path& file, F call) {
  try {
    call();
    ADD_FAILURE() << "no exception writing " << file;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::istringstream in(s);
  for (std::string part; std::getline(in, part, sep);) parts.push_back(part);
  return parts;
}

}  // namespace

TEST_F(IoTest, AtomicWriteReplacesWholeFileAndLeavesNoTmp) {
  const fs::path file = dir / "a.txt";
  write_text(file, "first version\n");
  EXPECT_EQ(read_text(file), "first version\n");
  write_text(file, "second\n");
  EXPECT_EQ(read_text(file), "second\n");
  EXPECT_EQ(temporary_path_for(file), dir / "a.txt.tmp");
  expect_no_tmp_files();
}

TEST_F(IoTest, AtomicWriteFailuresKeepTheOldFileAndRemoveTmp) {
  const fs::path file = dir / "a.txt";
  write_text(file, "complete\n");

  // The writer fails half-way: its exception passes through, the old file stays.
  EXPECT_THROW(write_file_atomically(file,
                                     [](std::ostream& os) {
                                       os << "half of the new";
                                       throw std::logic_error("writer failed");
                                     }),
               std::logic_error);
  EXPECT_EQ(read_text(file), "complete\n");

  // The stream goes bad (as on a full disk).
  expect_error_naming(file, [&] {
    write_file_atomically(file, [](std::ostream& os) {
      os << "partial";
      os.setstate(std::ios::badbit);
    });
  });
  EXPECT_EQ(read_text(file), "complete\n");

  // The rename fails: the target is a directory.
  fs::create_directory(dir / "sub");
  expect_error_naming(dir / "sub", [&] { write_text(dir / "sub", "x"); });
  expect_no_tmp_files();
}

TEST_F(IoTest, AtomicWriteIntoUnwritableDirectoryThrowsNamingThePath) {
  // A missing folder, and a "folder" that is a regular file: unwritable even for root.
  expect_error_naming(dir / "missing" / "a.txt", [&] { write_text(dir / "missing" / "a.txt", "x"); });
  write_text(dir / "plain", "not a folder");
  expect_error_naming(dir / "plain" / "a.txt", [&] { write_text(dir / "plain" / "a.txt", "x"); });
  EXPECT_FALSE(fs::exists(dir / "missing"));

  if (::geteuid() != 0) {  // permissions do not stop root
    const fs::path ro = dir / "readonly";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    expect_error_naming(ro / "a.txt", [&] { write_text(ro / "a.txt", "x"); });
    fs::permissions(ro, fs::perms::owner_all);
    EXPECT_TRUE(fs::is_empty(ro));
  }
  expect_no_tmp_files();
}

TEST_F(IoTest, PvdListsEveryDataSetWithItsTime) {
  PvdWriter pvd(dir);
  EXPECT_FALSE(fs::exists(dir / "particles.pvd"));
  const std::vector<std::pair<double, std::string>> sets = {
      {0.0, "particles_000000.vtu"}, {0.1, "particles_000001.vtu"}, {1.0 / 3.0, "a&b <\"odd\">.vtu"}};
  for (std::size_t i = 0; i < sets.size(); ++i) {
    pvd.add(sets[i].first, sets[i].second);
    EXPECT_EQ(pvd.size(), i + 1);
    const auto [status, out] = run_python("read_pvd.py", {pvd.file().string()});
    ASSERT_EQ(status, 0) << out;
    std::istringstream lines(out);
    std::string line;
    std::getline(lines, line);
    EXPECT_EQ(line, "root VTKFile Collection");
    for (std::size_t k = 0; k <= i; ++k) {
      std::string word, time;
      ASSERT_TRUE(lines >> word >> time) << out;
      std::getline(lines >> std::ws, line);
      EXPECT_EQ(word, "dataset");
      EXPECT_EQ(to_double(time), sets[k].first);
      EXPECT_EQ(line, sets[k].second);
    }
  }
  EXPECT_EQ(pvd.file(), dir / "particles.pvd");
  EXPECT_THROW(pvd.add(std::nan(""), "x.vtu"), std::invalid_argument);
  expect_no_tmp_files();
}

TEST_F(IoTest, SeriesCsvRoundTripsEveryValue) {
  const fs::path file = dir / "series.csv";
  std::vector<SeriesRow> rows;
  struct stat first {};
  {
    SeriesWriter series(file);
    for (long i = 0; i < 5; ++i) {
      const double t = 0.1 * i;
      rows.push_back({10 * i, t, 1.0 / (i + 3), 2.5e-7 * i, std::sqrt(2.0) * i, 1e300 / (i + 1), 0.5 * t,
                      t / 3, t / 7, 3 * t, -t, t * 1e-20, 1000 + i, static_cast<int>(i % 2), 0.25 * t,
                      7 * i});
      series.add(rows.back());
      if (i == 2) {
        series.flush();
        EXPECT_EQ(split(read_text(file), '\n').size(), 4u);  // header + 3 rows
        ASSERT_EQ(::stat(file.c_str(), &first), 0);
      }
    }
    EXPECT_EQ(series.rows().size(), 5u);
  }  // the destructor flushes the last two rows
  struct stat last {};
  ASSERT_EQ(::stat(file.c_str(), &last), 0);
  EXPECT_EQ(last.st_ino, first.st_ino) << "rows appended, not the file rewritten";
  const std::vector<std::string> lines = split(read_text(file), '\n');
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0],
            "step,time,kinetic_energy,strain_energy,gravity_work,plastic_dissipation,friction_work,"
            "transfer_dissipation,total_energy,"
            "mean_speed,max_speed,momentum_x,momentum_y,num_particles,stage,runout,yielding_points");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::vector<std::string> f = split(lines[i + 1], ',');
    ASSERT_EQ(f.size(), 17u) << lines[i + 1];
    const SeriesRow& r = rows[i];
    EXPECT_EQ(std::stol(f[0]), r.step);
    const double expected[] = {r.time,
                               r.kinetic_energy,
                               r.strain_energy,
                               r.gravity_work,
                               r.plastic_dissipation,
                               r.friction_work,
                               r.transfer_dissipation,
                               r.kinetic_energy + r.strain_energy + r.plastic_dissipation + r.friction_work +
                                   r.transfer_dissipation - r.gravity_work,
                               r.mean_speed,
                               r.max_speed,
                               r.momentum_x,
                               r.momentum_y};
    for (int k = 0; k < 12; ++k) EXPECT_EQ(to_double(f[k + 1]), expected[k]) << "column " << k + 1;
    EXPECT_EQ(std::stol(f[13]), r.num_particles);
    EXPECT_EQ(std::stoi(f[14]), r.stage);
    EXPECT_EQ(to_double(f[15]), r.runout);
    EXPECT_EQ(std::stol(f[16]), r.yielding_points);
  }
  expect_no_tmp_files();
}

TEST_F(IoTest, SummaryJsonIsValidAndEscaped) {
  Summary s{"error",
            "bad \"value\" in C:\\path\nline two\ttab \x01 caf\xc3\xa9 \xff end",
            1234,
            0.5,
            2.0,
            4000,
            1600,
            std::numeric_limits<double>::quiet_NaN(),
            std::numeric_limits<double>::infinity(),
            8,
            "slope \"A\".toml",
            "gimp",
            "usl",
            1e-5};
  s.phase_seconds = {{"stress_update_force", 0.25}, {"grid_update", 1.5}};
  s.version = "0.1.0";
  s.git_commit = "unknown";
  s.velocity_transfer = "xpic";
  s.xpic_order = 2;
  s.xpic_period = 2.0;
  s.volumetric_strain = "cell-average";
  const fs::path file = dir / "summary.json";
  write_summary_json(file, s);
  const auto [status, out] = run_python("read_json.py", {file.string()});
  ASSERT_EQ(status, 0) << out << "\n" << read_text(file);
  std::map<std::string, std::string> got;
  std::istringstream lines(out);
  for (std::string key, value; lines >> key && std::getline(lines >> std::ws, value);) got[key] = value;
  const std::map<std::string, std::string> expected = {
      {"status", "\"error\""},
      {"message", R"("bad \"value\" in C:\\path\nline two\ttab \u0001 caf\u00e9 \ufffd end")"},
      {"steps", "1234"},
      {"simulated_time", "0.5"},
      {"end_time", "2"},
      {"particles", "4000"},
      {"cells", "1600"},
      {"wall_seconds", "null"},
      {"particle_updates_per_second", "null"},
      {"memory", R"({"peak_bytes": null, "bytes_per_point": null})"},
      {"threads", "8"},
      {"scenario", R"("slope \"A\".toml")"},
      {"interpolation", "\"gimp\""},
      {"scheme", "\"usl\""},
      {"velocity_transfer", "\"xpic\""},
      {"xpic_order", "2"},
      {"xpic_period", "2"},
      {"volumetric_strain", "\"cell-average\""},
      {"time_step", "1e-05"},
      {"phase_seconds", R"({"stress_update_force": 0.25, "grid_update": 1.5})"},
      {"stages", "[]"},
      {"version", "\"0.1.0\""},
      {"git_commit", "\"unknown\""}};
  EXPECT_EQ(got, expected);
  EXPECT_EQ(json_string("\x7f"), "\"\x7f\"");
  EXPECT_EQ(json_string("\xed\xa0\x80"), "\"\\ufffd\\ufffd\\ufffd\"");  // a surrogate
  expect_no_tmp_files();
}
