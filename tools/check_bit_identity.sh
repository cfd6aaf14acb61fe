#!/usr/bin/env bash
# check_bit_identity.sh OLD_SPHSOLID NEW_SPHSOLID [WORKDIR]
#
# Runs every shipped case (cases/*/scene.cfg) at a low resolution and a short
# end time with both binaries, on both backends (native cpu and OpenCL, pocl
# on a CI machine), plus single and mixed precision on one case, and checks
# that the results are the same bits: `sphsolid compare --rtol 0 --atol 0`.
# For refactorings that must not change arithmetic (issue 32: the typed
# parameter block).  Prints one line per case and backend; exit status 1 if
# any pair differs or a run fails.  BACKENDS="cpu" limits the backends.
set -u
old=$(readlink -f "$1")
new=$(readlink -f "$2")
work=${3:-$(mktemp -d /tmp/bitid.XXXXXX)}
backends=${BACKENDS:-"cpu opencl"}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work"

# case | overrides (each run a few seconds on two cores)
cases=(
  "ball_plate_2d|resolution.dp=0.005 time.end=0.001"
  "ball_plate_3d|resolution.dp=0.01 time.end=0.0005"
  "colliding_balls_3d|resolution.dp=0.005 time.end=0.0004"
  "colliding_rings_2d|resolution.dp=0.002 time.end=0.0004"
  "high_velocity_impact|resolution.dp=4e-4 time.end=4e-7"
  "oscillating_plate_2d|resolution.ratio=6 time.end=0.02"
  "oscillating_plate_3d|resolution.dp=0.005 time.end=0.0003"
  "punch_2d|resolution.dp=0.1 time.end=1.5e-4"
  "spinning_cube_3d|resolution.dp=0.1 time.end=0.02"
  "spinning_plate_2d|resolution.dp=0.1 time.end=0.02"
  "taylor_bar_round|resolution.ratio=6 time.end=2e-6"
  "taylor_bar_square|resolution.dp=0.0015 time.end=2e-6"
  "tensile_2d|resolution.dp=0.05 time.end=5e-5"
  "bending_column_3d|resolution.dp=0.166666666666667 time.end=0.01 time.output_interval=0.005"
  "mesh_ball_3d|resolution.dp=0.01 time.end=0.0005 output.snapshot_interval=0"
  "mesh_gear_3d|resolution.dp=0.05 time.end=0.004"
  "taylor_green_2d|resolution.dp=0.05 time.end=0.2"
  "shu_osher_1d|time.end=0.005 time.output_interval=0.005"
  "cylinder_flow_2d|resolution.dp=0.25 time.end=1.0"
)
# precision variants on one case
extra=(
  "oscillating_plate_2d|resolution.ratio=6 time.end=0.02|single"
  "oscillating_plate_2d|resolution.ratio=6 time.end=0.02|mixed"
  "taylor_bar_square|resolution.dp=0.0015 time.end=2e-6|single"
)

status=0
run_pair() { # name overrides backend precision
  local name=$1 sets=$2 backend=$3 prec=$4 tag="$1-$3-$4" args=()
  for s in $sets; do args+=(--set "$s"); done
  for which in old new; do
    local bin=$old
    [ "$which" = new ] && bin=$new
    rm -rf "$work/$which-$tag"
    if ! "$bin" run "$root/cases/$name/scene.cfg" "${args[@]}" --backend "$backend" \
      --precision "$prec" --out "$work/$which-$tag" --quiet >"$work/$which-$tag.log" 2>&1; then
      echo "$tag: RUN FAILED ($which, see $work/$which-$tag.log)"
      status=1
      return
    fi
  done
  if "$new" compare "$work/old-$tag" "$work/new-$tag" --rtol 0 --atol 0 >"$work/cmp-$tag.log" 2>&1
  then
    echo "$tag: identical"
  else
    echo "$tag: DIFFERENT (see $work/cmp-$tag.log)"
    status=1
  fi
}

for backend in $backends; do
  for c in "${cases[@]}"; do
    run_pair "${c%%|*}" "${c#*|}" "$backend" double
  done
  for c in "${extra[@]}"; do
    IFS='|' read -r name sets prec <<<"$c"
    run_pair "$name" "$sets" "$backend" "$prec"
  done
done
exit $status
