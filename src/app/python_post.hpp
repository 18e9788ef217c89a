// `skred render`, `skred report` and the picture of `skred sweep` run the Python post-processing
// (python/skred-post.py, matplotlib + VTK from Debian's packages) with the system Python.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace skred {

// The Python interpreter used: $SKRED_PYTHON if set, else /usr/bin/python3 (the one Debian's
// python3-matplotlib and python3-vtk9 install into; a python3 earlier on PATH may lack them).
std::string post_python();

// Path of skred-post.py: the first that exists of <exe dir>/python/, <exe dir>/../share/skred/
// python/ and the source tree's python/ (compile-time). Throws std::runtime_error listing the
// places looked in if none has it.
std::filesystem::path find_post_script(const std::filesystem::path& exe);

// Replaces this process by `PYTHON -E -s -B skred-post.py ARGS...` (-E -s: no PYTHON*
// variables and no user site-packages, so Debian's modules are the ones imported; -B: no
// __pycache__ written into the source tree). Returns only if that
// fails, after printing why (with the packages to install) on stderr; the return value is the
// exit status to use (kMissingPython, or kError when the script is not found).
int exec_post(const std::vector<std::string>& args);

// Runs the same command as a child process and waits for it: its exit status (6 when Python
// is missing, as skred-post.py's own for a missing module).
int run_post(const std::vector<std::string>& args);

}  // namespace skred
