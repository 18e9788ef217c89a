// What a particle frame holds and how ([output] fields and compression): the default set,
// "all" and a custom list write exactly those arrays; a zlib-compressed Float32 frame reads
// back with VTK's reader value for value; georeferenced corners stay Float64; the scenario
// keys are validated with located errors.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "io/vtu_writer.hpp"
#include "io_test_util.hpp"
#include "post/strain_measures.hpp"
#include "scenario/output_fields.hpp"
#include "scenario/scenario.hpp"
#include "vtu_test_util.hpp"

using namespace skred;
using namespace skred::iotest;
namespace fs = std::filesystem;

namespace {

// n points with distinct, non-round values in every field, and every optional input.
struct Frame {
  Particles<2> P;
  std::vector<Sym3> smoothed;
  std::vector<MaterialStrength> strength = {{0.5, 1e4}};
  std::vector<Mat3> Fe;
  std::vector<Sym3> from_fe;

  explicit Frame(int n) {
    for (int i = 0; i < n; ++i) {
      P.add(Vec<2>(0.1 * (i % 1000), 0.1 * (i / 1000)), Vec<2>(std::sin(i), 1.0 / (i + 3)), 2.0, 0.01,
            Vec<2>(0.05, 0.05), 0, i % 2);
      P.F[i] << 1.0 + 1e-3 * std::cos(i), 1e-4 * i / n, 0.0, 1.0 - 7e-4 * std::sin(i);
      P.x[i] += Vec<2>(1e-3 * std::cos(3.0 * i), -2e-3 * i / n);
      P.stress[i] << -1e4 - 17.3 * i, -2e4 + std::cos(i), -1.5e4, 1e3 * std::sin(i);
      P.state[i].plastic_shear_strain = 1e-3 * (i % 7) / 3.0;
      P.state[i].yielding = i % 3 == 0;
      smoothed.push_back(full_stress<2>(P.stress[i]) * 0.9);
      Fe.push_back(deformation3<2>(P.F[i]));
      from_fe.push_back(full_stress<2>(P.stress[i]) * 1.1);
    }
  }
  ParticleFields extra() const { return {&smoothed, &strength, &Fe, &from_fe}; }
};

std::set<std::string> names_of(const VtuInfo& info) {
  std::set<std::string> n;
  for (const auto& [name, a] : info.arrays) n.insert(name);
  return n;
}

std::set<std::string> as_set(const std::vector<std::string>& v) { return {v.begin(), v.end()}; }

}  // namespace

TEST_F(IoTest, OutputFieldsWriteExactlyTheRequestedArrays) {
  const Frame f(3);
  const std::vector<std::string> custom = {"speed", "Fp", "material_id"};
  for (const auto& fields : {output_fields::defaults(), output_fields::all(), custom}) {
    const fs::path file = dir / "p.vtu";
    write_particles_vtu(file, f.P, f.extra(), {fields, true});
    const VtuInfo info = read_vtu(file, "0");
    EXPECT_EQ(names_of(info), as_set(fields));
    EXPECT_EQ(info.cells, 3);
  }
  EXPECT_EQ(output_fields::all().size(), 28u);  // every field the writer has
  EXPECT_THROW(write_particles_vtu(dir / "x.vtu", f.P, f.extra(), {{"speed", "sped"}, true}),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "x.vtu"));
}

TEST_F(IoTest, CompressedFloat32FrameReadsBackByValue) {
  const int n = 3000;
  const Frame f(n);
  const fs::path packed = dir / "packed.vtu", raw = dir / "raw.vtu";
  write_particles_vtu(packed, f.P, f.extra(), {output_fields::all(), true});
  write_particles_vtu(raw, f.P, f.extra(), {output_fields::all(), false});
  const std::string head = read_text(packed).substr(0, 400), raw_head = read_text(raw).substr(0, 400);
  EXPECT_NE(head.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos) << head;
  EXPECT_EQ(raw_head.find("compressor"), std::string::npos) << raw_head;
  EXPECT_LT(fs::file_size(packed), fs::file_size(raw));

  const std::string cells = "0 1 1234 2999";
  const VtuInfo a = read_vtu(packed, cells), b = read_vtu(raw, cells);
  EXPECT_EQ(a.point_type, "float32");
  ASSERT_EQ(names_of(a), as_set(output_fields::all()));
  for (const auto& [name, arr] : a.arrays) EXPECT_EQ(arr.values, b.arrays.at(name).values) << name;
  EXPECT_EQ(a.point, b.point);
  for (int c : {0, 1, 1234, 2999}) {
    const auto value = [&](const std::string& name, int k = 0) {
      return a.arrays.at(name).values.at({c, k});
    };
    const Sym3 s = full_stress<2>(f.P.stress[c]);
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(value("stress", k), f32(s[k]));
      EXPECT_EQ(value("smoothed_stress", k), f32(f.smoothed[c][k]));
      EXPECT_EQ(value("stress_from_Fe", k), f32(f.from_fe[c][k]));
    }
    EXPECT_EQ(value("velocity", 0), f32(f.P.v[c][0]));
    EXPECT_EQ(value("speed"), f32(f.P.v[c].norm()));
    EXPECT_EQ(value("displacement", 1), f32(f.P.x[c][1] - f.P.x_ref[c][1]));
    EXPECT_EQ(value("plastic_shear_strain"), f32(f.P.state[c].plastic_shear_strain));
    EXPECT_EQ(value("det_F"), f32(f.P.F[c].determinant()));
    EXPECT_EQ(value("yielding"), f.P.state[c].yielding);
    EXPECT_EQ(value("body_id"), f.P.body[c]);
    EXPECT_EQ(value("F", 1), f32(f.P.F[c](0, 1)));
    // A corner of the voxel, x_p + F_p (l0x, l0y) (Thesis eq. 3.6), within Float32 rounding.
    const Vec<2> corner = f.P.x[c] + f.P.F[c] * f.P.half0[c];
    const Vec<2>& got = a.point.at(4 * c + 2);
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(got[d], corner[d], f32_tolerance(corner[d]) + 1e-15);
  }
}

// `skred check` estimates a frame's size from the chosen fields (scenario/estimate.cpp):
// an uncompressed frame is that per point plus its XML header.
TEST_F(IoTest, UncompressedFrameSizeIsTheCheckEstimate) {
  const int n = 2000;
  const Frame f(n);
  for (const auto& fields : {output_fields::defaults(), output_fields::all()}) {
    const fs::path file = dir / "raw.vtu";
    write_particles_vtu(file, f.P, f.extra(), {fields, false});
    const double data = n * output_fields::uncompressed_bytes_per_point(fields, 2);
    const double size = static_cast<double>(fs::file_size(file));
    EXPECT_GT(size, data);
    EXPECT_LT(size, data + 8192) << "XML header and array byte counts";
  }
}

TEST_F(IoTest, GeoreferencedCornersStayFloat64) {
  Particles<2> P;  // UTM-like coordinates: Float32 would round them to 3 cm
  P.add(Vec<2>(512345.125, 6200000.375), Vec<2>(0.0, 0.0), 1.0, 0.01, Vec<2>(0.05, 0.05), 0, 0);
  const fs::path file = dir / "utm.vtu";
  write_particles_vtu(file, P);
  const VtuInfo info = read_vtu(file);
  EXPECT_EQ(info.point_type, "float64");
  EXPECT_EQ(info.point.at(2)[0], 512345.175);
  EXPECT_EQ(info.point.at(2)[1], 6200000.425);
}

// The write time of a frame of 10^6 points, default and all fields, compressed and raw:
// a measurement, not a test (scripts/vtu_size.sh runs it; no time is asserted). The values
// are synthetic, so the sizes printed here are not those of a real run.
TEST_F(IoTest, DISABLED_WriteTimeAtAMillionPoints) {
  const Frame f(1000000);
  for (const char* set : {"default", "all"})
    for (bool compress : {true, false}) {
      const auto& fields = std::string(set) == "all" ? output_fields::all() : output_fields::defaults();
      const fs::path file = dir / "big.vtu";
      const auto start = std::chrono::steady_clock::now();
      write_particles_vtu(file, f.P, f.extra(), {fields, compress});
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("write 10^6 points, %s fields, %s: %.2f s, %.1f B/point (synthetic values)\n", set,
                  compress ? "zlib" : "raw", s, static_cast<double>(fs::file_size(file)) / 1e6);
    }
}

namespace {

std::string output_error(const std::string& output) {
  const std::string text = read_text(fs::path(SKRED_SOURCE_DIR) / "tests" / "data" / "minimal.toml") +
                           "\n[output]\n" + output + "\n";
  try {
    parse_any_scenario(text, "t.toml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> fields_of(const std::string& output) {
  const std::string text = read_text(fs::path(SKRED_SOURCE_DIR) / "tests" / "data" / "minimal.toml") +
                           "\n[output]\n" + output + "\n";
  return std::get<Scenario>(parse_any_scenario(text, "t.toml")).output_fields;
}

}  // namespace

TEST(OutputFields, ScenarioKeyChoosesTheFields) {
  EXPECT_EQ(as_set(fields_of("")), as_set(output_fields::defaults()));
  EXPECT_EQ(fields_of("fields = \"all\""), output_fields::all());
  EXPECT_EQ(fields_of("fields = \"default\""), fields_of(""));
  // In the file's order, each once.
  EXPECT_EQ(fields_of("fields = [\"Fp\", \"speed\", \"Fp\"]"), (std::vector<std::string>{"speed", "Fp"}));
  std::vector<std::string> more = fields_of("fields = [\"default\", \"hencky_strain\"]");
  EXPECT_EQ(more.size(), output_fields::defaults().size() + 1);
  EXPECT_NE(std::find(more.begin(), more.end(), "hencky_strain"), more.end());

  const std::string e = output_error("fields = [\"speed\", \"presure\"]");
  EXPECT_NE(e.find("t.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("output.fields"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown value \"presure\""), std::string::npos) << e;
  for (const char* allowed : {"\"default\"", "\"all\"", "\"mean_stress_p\"", "\"stress_from_Fe\""})
    EXPECT_NE(e.find(allowed), std::string::npos) << e;
  EXPECT_NE(output_error("fields = []"), "");
  EXPECT_NE(output_error("fields = 3"), "");
  EXPECT_NE(output_error("compression = \"yes\"").find("output.compression"), std::string::npos);
  EXPECT_EQ(std::get<Scenario>(
                parse_any_scenario(read_text(fs::path(SKRED_SOURCE_DIR) / "tests" / "data" / "minimal.toml") +
                                       "\n[output]\ncompression = false\n",
                                   "t.toml"))
                .output_compression,
            false);
}
