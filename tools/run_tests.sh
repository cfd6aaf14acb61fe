#!/usr/bin/env bash
# The whole test suite: a warnings-as-errors release build with every test on
# the native backend and on OpenCL (pocl in CI), then an ASan/UBSan build
# running the native-backend tests, then the clang-format check.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
# OpenMP threads sleep at barriers: the CI machines are shared 2-core VMs.
export OMP_WAIT_POLICY=passive

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSPHSOLID_WERROR=ON
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPHSOLID_WERROR=ON \
      -DSPHSOLID_SANITIZE=ON
cmake --build build-sanitize -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-sanitize --output-on-failure -j "$jobs" -L cpu

# formatting: the sources match .clang-format
git ls-files 'host/*.c' 'host/*.h' 'device/*.h' 'device/*.cl' 'tests/*.c' 'tests/*.h' |
  xargs clang-format --dry-run --Werror
echo "all tests passed"
