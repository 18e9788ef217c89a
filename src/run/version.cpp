#include "run/version.hpp"

#include "skred_version.hpp"  // generated in the build folder (cmake/skred_version.cmake)

namespace skred {

const char* version() { return SKRED_VERSION; }
const char* git_commit() { return SKRED_GIT_COMMIT; }

}  // namespace skred
