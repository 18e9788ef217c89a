// The 3D explicit solver (explicit_solver_impl.hpp), in its own translation unit.
#include "solver/explicit_solver_impl.hpp"

namespace skred {

template class ExplicitSolver<3>;

}  // namespace skred
