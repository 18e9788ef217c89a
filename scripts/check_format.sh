#!/usr/bin/env bash
# Fails (and lists the files) when a C++ source of src/ or tests/ differs from what
# clang-format makes of it with the repository's .clang-format. Fix with:
#   clang-format -i $(git ls-files 'src/*.[ch]pp' 'tests/*.[ch]pp')
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "clang-format is not installed (scripts/install-deps.sh installs it)"; exit 1; }
bad=0
while IFS= read -r f; do
  if ! clang-format --dry-run --Werror "$f" >/dev/null 2>&1; then
    echo "not clang-formatted: $f"
    bad=1
  fi
done < <(find src tests -name '*.cpp' -o -name '*.hpp' | sort)
exit $bad
