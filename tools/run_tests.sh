#!/usr/bin/env bash
# The whole test suite: a warnings-as-errors release build with every test on
# the native backend and on OpenCL (pocl in CI), then an ASan/UBSan build
# running the native-backend tests, then the clang-format and pyflakes checks.
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

# fuzzing: libFuzzer over the scene parser, validator and particle generator
# for 60 s, over the run directory's writers for 20 s, over the mesh reader
# for 20 s and over the checkpoint reader for 20 s, from the seed
# corpora (tests/fuzz; any crash, leak, UB report, hang or broken invariant
# fails the script and leaves crash-* in build-fuzz)
if ! command -v clang >/dev/null; then
  echo "fuzzing skipped: no clang (apt-get install clang libclang-rt-14-dev)"
elif [ ! -f "$(clang -print-file-name=libclang_rt.fuzzer-x86_64.a)" ]; then
  echo "fuzzing skipped: clang has no libFuzzer runtime (apt-get install libclang-rt-14-dev)"
else
  cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DSPHSOLID_WERROR=ON -DSPHSOLID_FUZZ=ON
  cmake --build build-fuzz --target fuzz_scene fuzz_writers fuzz_mesh fuzz_checkpoint -j "$jobs"
  mkdir -p build-fuzz/corpus build-fuzz/writers-corpus
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0 \
    build-fuzz/tests/fuzz/fuzz_scene -max_total_time=60 -timeout=10 -rss_limit_mb=2048 \
    -dict=tests/fuzz/scene.dict -artifact_prefix=build-fuzz/ \
    build-fuzz/corpus tests/fuzz/corpus tests/fuzz/regressions
  # the run-directory writers for 20 s: names and free text of arbitrary bytes
  # through timeseries.csv and summary.json, read back (tests/fuzz/fuzz_writers.c);
  # each input writes a small run directory, on /dev/shm where there is one
  # (about 8x the inputs per second of a disk-backed /tmp)
  fuzz_tmp=${TMPDIR:-/tmp}
  if [ -d /dev/shm ] && [ -w /dev/shm ]; then fuzz_tmp=/dev/shm; fi
  TMPDIR=$fuzz_tmp LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0 \
    build-fuzz/tests/fuzz/fuzz_writers -max_total_time=20 -timeout=10 -rss_limit_mb=2048 \
    -max_len=1024 -artifact_prefix=build-fuzz/ build-fuzz/writers-corpus tests/fuzz/writers_corpus
  # the mesh reader for 20 s: STL and OBJ bytes through assimp, the welding, the
  # checks and the search tree (tests/fuzz/fuzz_mesh.c); the slow unwinder shows
  # assimp's frames for its leak suppressions (tests/fuzz/lsan.supp)
  mkdir -p build-fuzz/mesh-corpus
  ASAN_OPTIONS=fast_unwind_on_malloc=0 \
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0 \
    build-fuzz/tests/fuzz/fuzz_mesh -max_total_time=20 -timeout=10 -rss_limit_mb=2048 \
    -max_len=4096 -artifact_prefix=build-fuzz/ build-fuzz/mesh-corpus tests/fuzz/mesh_corpus \
    tests/fuzz/mesh_regressions
  # the checkpoint reader for 20 s: a valid checkpoint edited value by value,
  # resized, retyped and cut, read as a restart reads it (tests/fuzz/fuzz_checkpoint.c);
  # its checkpoint is rewritten for each input, on /dev/shm where there is one
  mkdir -p build-fuzz/checkpoint-corpus
  TMPDIR=$fuzz_tmp LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0 \
    build-fuzz/tests/fuzz/fuzz_checkpoint -max_total_time=20 -timeout=10 -rss_limit_mb=2048 \
    -max_len=192 -artifact_prefix=build-fuzz/ build-fuzz/checkpoint-corpus \
    tests/fuzz/checkpoint_corpus
fi

# formatting: the sources match .clang-format
git ls-files 'host/*.c' 'host/*.h' 'device/*.h' 'device/*.cl' 'tests/*.c' 'tests/*.h' |
  xargs clang-format --dry-run --Werror
# the Python tests and tools: no unused names, undefined names or dead f-strings
git ls-files '*.py' | xargs pyflakes3
echo "all tests passed"
