#!/usr/bin/env bash
# Checks that every C++ source is formatted by the repository's .clang-format
# (Debian's clang-format). Exits non-zero and names the files that are not.
# Fix with: clang-format -i $(git ls-files '*.h' '*.cpp')
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
mapfile -t files < <(git ls-files '*.h' '*.cpp')
clang-format --dry-run -Werror "${files[@]}"
echo "check-format: ${#files[@]} files formatted"
