// Reading a particle .vtu back with VTK's own XML reader (tests/scripts/read_vtu.py through
// /usr/bin/python3) into a map of arrays, for the result-file tests.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io_test_util.hpp"

namespace skred::iotest {

// A double as the Float32 of a frame holds it (the writer rounds to nearest).
inline double f32(double x) { return static_cast<float>(x); }
// Half a Float32 unit in the last place of x: how far a stored value may lie from x.
inline double f32_tolerance(double x) { return std::abs(x) * 0x1p-24; }

// What tests/scripts/read_vtu.py reports about a file.
struct VtuArray {
  int components = 0;
  std::string vtk_class;  // the values by meaning: float64, uint8, int16, ... (read_vtu.py)
  std::map<int, std::string> component_names;
  std::map<std::pair<int, int>, double> values;  // (cell, component) -> value
};
struct VtuInfo {
  long cells = -1, points = -1, point_arrays = -1;
  std::string point_type;  // float32 or float64
  std::map<int, int> cell_type;
  std::map<int, std::vector<int>> cell_points;
  std::map<int, Vec<2>> point;
  std::map<std::string, VtuArray> arrays;
};

// Reads `file` with VTK's XML reader (through /usr/bin/python3) and parses the report.
inline VtuInfo read_vtu(const std::filesystem::path& file, const std::string& cells = "") {
  require_python_vtk();
  std::vector<std::string> args = {file.string()};
  std::istringstream ids(cells);
  for (std::string id; ids >> id;) args.push_back(id);
  const auto [status, out] = run_python("read_vtu.py", args);
  EXPECT_EQ(status, 0) << out;
  EXPECT_EQ(out.find("ERROR"), std::string::npos) << out;
  VtuInfo info;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "cells")
      in >> info.cells;
    else if (key == "points")
      in >> info.points;
    else if (key == "pointtype")
      in >> info.point_type;
    else if (key == "pointarrays")
      in >> info.point_arrays;
    else if (key == "celltype") {
      int c;
      in >> c;
      in >> info.cell_type[c];
    } else if (key == "cellpoints") {
      int c, id;
      in >> c;
      while (in >> id) info.cell_points[c].push_back(id);
    } else if (key == "point") {
      int i;
      std::string x, y, z;
      in >> i >> x >> y >> z;
      info.point[i] = Vec<2>(to_double(x), to_double(y));
      EXPECT_EQ(to_double(z), 0.0);
    } else if (key == "array") {
      std::string name;
      in >> name;
      in >> info.arrays[name].components >> info.arrays[name].vtk_class;
    } else if (key == "compname") {
      std::string name;
      int k;
      in >> name >> k;
      in >> info.arrays[name].component_names[k];
    } else if (key == "value") {
      std::string name, v;
      int c, k;
      in >> name >> c >> k >> v;
      info.arrays[name].values[{c, k}] = to_double(v);
    } else {
      ADD_FAILURE() << "unexpected line from read_vtu.py: " << line;
    }
  }
  return info;
}

}  // namespace skred::iotest
