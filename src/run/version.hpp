// The version of skred and the git commit it was built from (configure time; "unknown" when
// built outside a git checkout).
#pragma once

namespace skred {

const char* version();
const char* git_commit();

}  // namespace skred
