#!/usr/bin/env bash
# Prepare a self-contained bundle for running sphsolid on a GPU machine that has the NVIDIA
# driver but no OpenCL ICD loader, HDF5 or libconfig (the lent NVIDIA machines of this
# workplace: docs/gpu.md). Builds a Release tree here (Debian 12), and puts into .ocl/:
#   lib/  Debian's ICD loader (ocl-icd-libopencl1) and every shared library the binaries need
#         beyond glibc;  bin/clinfo  (Debian's clinfo, to check the loader sees the driver).
# On the GPU machine: `source tools/gpu_env.sh` (carry .ocl and the build folder).
#   tools/gpu_bundle.sh [build-folder]        (default build-gpu)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-gpu}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DSPHSOLID_WERROR=ON >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null
rm -rf .ocl && mkdir -p .ocl/lib .ocl/bin .ocl/debs .ocl/root
(cd .ocl/debs && apt-get download -q ocl-icd-libopencl1 clinfo >/dev/null 2>&1)
for deb in .ocl/debs/*.deb; do dpkg-deb -x "$deb" .ocl/root; done
cp -L .ocl/root/usr/lib/x86_64-linux-gnu/libOpenCL.so.1 .ocl/lib/
cp .ocl/root/usr/bin/clinfo .ocl/bin/
# glibc's own libraries stay: the GPU machine's glibc is newer than Debian 12's
ldd "$build/sphsolid" "$build"/tests/test_* | awk '/=> \//{print $3}' | sort -u |
  grep -Ev '/(libc|libm|libdl|libpthread|librt|libresolv|ld-linux[^/]*)\.so' |
  grep -v libOpenCL | while read -r lib; do cp -L "$lib" .ocl/lib/; done
rm -rf .ocl/root .ocl/debs
du -sh .ocl "$build" | sed 's/^/bundle: /'
