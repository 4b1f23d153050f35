#!/usr/bin/env bash
# The code checks of the test command (scripts/test.sh), each configured in the
# repository and expected clean:
#   1. clang-format --dry-run -Werror on the C++ of rodcore/, tests/cpp, bench, fuzz (.clang-format);
#   2. flake8 on every Python file (.flake8);
#   3. mypy on the toolkit's packages mdbridge, dna_models, dnarod (pyproject.toml [tool.mypy]).
# Usage: bash scripts/check.sh [format|lint|types]...   (default: all three)
set -euo pipefail
source "$(dirname "$0")/env.sh"
cd "$DNAROD_ROOT"
checks=("$@")
[ ${#checks[@]} -gt 0 ] || checks=(format lint types)
for c in "${checks[@]}"; do
  case "$c" in
    format)
      echo "== format (clang-format --dry-run -Werror)"
      mapfile -t files < <(find rodcore tests/cpp bench fuzz -type f \( -name '*.cpp' -o -name '*.hpp' \) | sort)
      clang-format --dry-run -Werror "${files[@]}" \
        || { echo "format: run  clang-format -i FILE  on the files above (style: .clang-format)" >&2; exit 1; }
      echo "format: ${#files[@]} files clean" ;;
    lint)
      echo "== lint (flake8)"
      "$PYTHON" -m flake8
      echo "lint: clean" ;;
    types)
      echo "== types (mypy)"
      # The folder workflows/ is the package dnarod (pyproject.toml, package-dir); mypy
      # cannot follow that mapping, so it gets the folder under its import name.
      MYPY_DIR="$DNAROD_BUILD/mypy"
      mkdir -p "$MYPY_DIR/path"
      ln -sfn "$DNAROD_ROOT/workflows" "$MYPY_DIR/path/dnarod"
      MYPYPATH="$MYPY_DIR/path" "$PYTHON" -m mypy --cache-dir "$MYPY_DIR/cache" \
        -p mdbridge -p dna_models -p dnarod ;;
    *) echo "check.sh: unknown check '$c' (allowed: format, lint, types)" >&2; exit 2 ;;
  esac
done
