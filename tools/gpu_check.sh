#!/usr/bin/env bash
# One call's worth of GPU work on a machine prepared by tools/gpu_bundle.sh (carry .ocl and
# build-gpu): the device and its bandwidth, every OpenCL test body on it, then the benchmarks
# (docs/gpu.md; what the 2026-11-23 H100 session ran in three calls), each stage skipped when
# the time budget is spent.  Logs and JSON go to OUTDIR (default $OUT, else /tmp/gpu-check).
#   tools/gpu_check.sh [budget-seconds, default 560] [stages: env tests fluids loop bench3d bench evr3d]
# (evr3d, the 3D plate's error-against-run-time ladder at H/dp = 3, 5, 9, is not in the default;
# fluids: the fluid test bodies on the GPU and the cylinder's GPU target, docs/fluids.md)
set -u
cd "$(dirname "$0")/.." || exit 1
budget=${1:-560}
shift || true
stages=${*:-env tests fluids loop bench3d bench}
out=${OUT:-/tmp/gpu-check}
mkdir -p "$out"
start=$(date +%s)
left() { echo $((budget - ($(date +%s) - start))); }
want() { case " $stages " in *" $1 "*) return 0 ;; esac; return 1; }
exec > >(tee -a "$out/gpu-check.log") 2>&1
# shellcheck source=/dev/null
source tools/gpu_env.sh
bin=$PWD/build-gpu
export SPHSOLID_BIN=$bin/sphsolid SPHSOLID_SOURCE_DIR=$PWD
py=python3
if want env; then
  echo "== device"
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null
  .ocl/bin/clinfo -l
  "$bin/sphsolid" devices
  "$bin/sphsolid" bandwidth --backend opencl --size-mb 1024
fi
if want tests; then
  echo "== OpenCL test bodies ($(left) s left)"
  for t in test_neighbours test_plate test_spinning_plate test_formulations test_contact \
    test_tlsph; do
    s=$(date +%s)
    timeout 120 "$bin/tests/$t" opencl >"$out/$t.log" 2>&1
    echo "$t: exit $?, $(($(date +%s) - s)) s; $(tail -1 "$out/$t.log")"
  done
  timeout 120 "$bin/tests/test_cross_check" >"$out/test_cross_check.log" 2>&1
  echo "test_cross_check: exit $?; $(tail -1 "$out/test_cross_check.log")"
  for t in test_precision test_walls test_monitor; do
    timeout 120 $py "tests/$t.py" opencl >"$out/$t.log" 2>&1
    echo "$t: exit $?; $(tail -1 "$out/$t.log")"
  done
fi
if want fluids; then
  # The fluid formulations on the GPU: their OpenCL test bodies, then the cylinder of seed 004
  # §4.3 (cases/cylinder_flow_2d): dp = 1/10 to t = 300 whole (the 2-core machine's speed
  # case, with its C_D, lift amplitude and St beside the native backend's) and the GPU target,
  # dp = 1/30 (1.35 M particles) to t = 300 in <= 10 minutes, run to t = CYL30_END (default 30)
  # and its time to t = 300 extrapolated in proportion to simulated time (printed as such).
  echo "== fluids ($(left) s left)"
  for t in test_fluids test_cylinder test_step_clock; do
    [ "$(left)" -gt 60 ] || { echo "$t opencl: skipped ($(left) s left)"; continue; }
    s=$(date +%s)
    timeout 240 $py "tests/$t.py" opencl >"$out/$t-opencl.log" 2>&1
    echo "$t opencl: exit $?, $(($(date +%s) - s)) s; $(tail -1 "$out/$t-opencl.log")"
  done
  for run in "0.1|300" "0.0333333333333333|${CYL30_END:-30}"; do
    IFS='|' read -r dp end <<<"$run"
    [ "$(left)" -gt 90 ] || { echo "cylinder dp=$dp t=$end: skipped ($(left) s left)"; continue; }
    rm -rf "$out/cylinder-run"
    timeout $(($(left) - 30)) "$bin/sphsolid" run cases/cylinder_flow_2d/scene.cfg \
      --backend opencl --quiet --out "$out/cylinder-run" --set "resolution.dp=$dp" \
      --set "time.end=$end" --set output.snapshot_interval=1000 >"$out/cylinder-run.log" 2>&1
    rc=$?
    echo "cylinder dp=$dp t=$end: exit $rc; $($py -c "
import json, sys
s = json.load(open(sys.argv[1]))
m, t, wall = s['metrics'], s['simulated_time'], s['wall_time_s']
line = '%d particles, %d steps, %.1f s (setup %.1f s), %.3g particle-steps/s on %s' % (
    s['particle_count'], s['acoustic_steps'], wall, s['setup_time_s'],
    s['particle_substeps_per_second'], s['device'])
if t >= 300:
    line += '; C_D %.4f, C_L amplitude %.4f, St %.4f over t >= %g' % (
        m['mean_drag_coefficient'], m['lift_amplitude'], m['strouhal_number'],
        m['force_window_start'])
else:
    line += '; to t = 300 extrapolated: %.0f s' % (s['setup_time_s'] +
        (wall - s['setup_time_s']) * 300.0 / t)
print(line)" "$out/cylinder-run/summary.json" 2>&1 | tail -1)"
    cp "$out/cylinder-run/summary.json" "$out/cylinder-dp$dp-t$end-summary.json" 2>/dev/null
  done
  rm -rf "$out/cylinder-run"
fi
if want loop; then
  # the substep loop (device/substep_loop.cl): bit for bit the per-pass runs on the GPU (its
  # tree reduction), then the small scenes' time with a launch per pass against the loop
  echo "== substep loop ($(left) s left)"
  timeout 240 $py tests/test_substep_loop.py >"$out/test_substep_loop.log" 2>&1
  echo "test_substep_loop: exit $?; $(tail -1 "$out/test_substep_loop.log")"
  plate=cases/oscillating_plate_2d/scene.cfg
  for run in "plate H/dp=10 t=1|$plate|time.end=1" \
    "plate H/dp=20 t=0.2|$plate|resolution.ratio=20 time.end=0.2 time.output_interval=0.1" \
    "cylinder small t=20|cases/cylinder_flow_2d/small.cfg|time.end=20" \
    "column dp=1/6 t=0.5|cases/bending_column_3d/scene.cfg|resolution.dp=0.166666666666667 time.end=0.5"; do
    IFS='|' read -r label scene sets <<<"$run"
    [ "$(left)" -gt 60 ] || { echo "loop timing $label: skipped"; continue; }
    for per in 1 0 1 0; do
      args=()
      for s in $sets; do args+=(--set "$s"); done
      rm -rf "$out/loop-run"
      timeout 120 "$bin/sphsolid" run "$scene" --backend opencl --quiet --out "$out/loop-run" \
        --substeps-per-launch "$per" "${args[@]}" >/dev/null 2>&1
      echo "loop timing $label, --substeps-per-launch $per: $($py -c "import json; s = json.load(open('$out/loop-run/summary.json')); print(s['particle_count'], 'particles', s['acoustic_steps'], 'substeps', s.get('substeps_per_launch'), 'per launch', round(s['wall_time_s'], 2), 's')" 2>&1)"
    done
  done
  rm -rf "$out/loop-run"
fi
if want bench3d; then
  for p in mixed single double; do
    [ "$(left)" -gt 240 ] || { echo "bench3d $p: skipped ($(left) s left)"; continue; }
    timeout $(($(left) - 20)) $py tools/bench.py --json "$out/bench-plate3d-h9-$p.json" \
      --backends opencl --precisions "$p" --plate-ratios --spinning-end 0 --plate3d-ratios 9 \
      --single-run --label "3D plate H/dp = 9, timing from the profiled run" >/dev/null 2>&1
    echo "bench3d $p: exit $?; $(grep -h '^| 3D plate (2,2) H/dp=9 | 0.1' "$out/bench-plate3d-h9-$p.md" 2>/dev/null)"
  done
fi
if want bench; then
  if [ "$(left)" -gt 180 ]; then
    timeout $(($(left) - 10)) $py tools/bench.py --json "$out/bench-gpu.json" --backends opencl \
      --precisions double --plate-ratios 10 20 30 --plate3d-ratios 3 5 >/dev/null 2>&1
    echo "bench: exit $?"
    grep -hE '^\| (plate|spinning|3D plate)' "$out/bench-gpu.md" 2>/dev/null | head -8
  else
    echo "bench: skipped ($(left) s left)"
  fi
fi
if want evr3d; then
  if [ "$(left)" -gt 200 ]; then
    timeout $(($(left) - 10)) $py tools/error_vs_runtime.py --backends opencl \
      --formulations enog-a gnog-a --precisions double mixed single --ratios --dps \
      --plate3d-ratios 3 5 9 --work /tmp/evr3d --csv "$out/error-vs-runtime-plate3d.csv" \
      --png "$out/error-vs-runtime-plate3d.png" --label "3D plate ladder" 2>&1 | tail -20
  else
    echo "evr3d: skipped ($(left) s left)"
  fi
fi
echo "== done after $(($(date +%s) - start)) s; results in $out"
