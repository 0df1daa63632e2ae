#!/usr/bin/env bash
# Formats impm's C++ sources in place with clang-format 14 and the repository's .clang-format.
# The ctest format_check (run by CI) fails on any file this would change.
#
#   cmake/format.sh            # format every .cpp/.hpp under core, physics, solvers, apps and test
#   cmake/format.sh FILE...    # format the files given
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT="${CLANG_FORMAT:-$(command -v clang-format-14 || true)}"
if [ -z "$CLANG_FORMAT" ]; then
  echo "format.sh: error: clang-format-14 not found (cmake/setup-deps.sh installs it)" >&2
  exit 2
fi
if [ $# -gt 0 ]; then
  files=("$@")
else
  mapfile -t files < <(find core physics solvers apps test -name '*.cpp' -o -name '*.hpp' | sort)
fi
"$CLANG_FORMAT" -i --style=file "${files[@]}"
