#!/usr/bin/env bash
# Instructions a ray, raylab against Embree, on the rays one kind of ray of a shipped scene casts:
# a count that a busy machine does not move, beside the peer bench's times, which it does.
#
#     benches/peer/instructions.sh [SCENE] [KIND]      (default: render-cornell-box refraction)
#
# Needs valgrind (apt-get install valgrind) and python3 with embreex and numpy. raylab's side is
# examples/ray_kind_loop (the bench's casts, one thread), counted inside `cast_run_again` over two
# casts. Embree's is benches/peer/embree_rays.py on the same rays and the same world-space
# triangles (`DUMP`), one thread, counted inside Embree's own queries (rtcIntersect1 or
# rtcOccluded1, called once a ray) over three casts (the count of rays that met something, one
# warm-up cast, one timed): not Python's loop around them, nor Embree's idle threads. Under
# valgrind both sides take their AVX2 code (valgrind has no AVX-512): raylab's packets test their
# boxes eight rays at a time there, not sixteen as on a processor with AVX-512.
set -euo pipefail
scene=${1:-render-cornell-box}
kind=${2:-refraction}
here=$(cd "$(dirname "$0")/../.." && pwd)
command -v valgrind > /dev/null || { echo "instructions.sh needs valgrind (apt-get install valgrind)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$here"
cargo build --release --example ray_kind_loop --quiet
loop=target/release/examples/ray_kind_loop
rays=$(DUMP="$work" SCENE="$scene" KIND="$kind" REPS=1 "$loop" | sed -n 's/.*: \([0-9]*\) rays,.*/\1/p')
# Valgrind must run the interpreter itself, not a launcher script (pyenv's shims are scripts).
python=$(python3 -c 'import sys; print(sys.executable)')
count() { # the program's instructions, from callgrind's summary
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
ours=$(SCENE="$scene" KIND="$kind" REPS=1 count --toggle-collect='raylab::render::ray_log::cast_run_again*' "$loop")
query=$(case $kind in shadow | occlusion) echo occluded ;; *) echo intersect ;; esac)
theirs=$(count --toggle-collect=rtcIntersect1 --toggle-collect=rtcOccluded1 \
    "$python" benches/peer/embree_rays.py --obj "$work/scene.obj" --rays "$work/$kind.f32" \
    --query "$query" --threads 1 --warm-ms 0 --reps 1)
python3 - "$scene" "$kind" "$rays" "$ours" "$theirs" << 'PY'
import sys
scene, kind, rays, ours, theirs = sys.argv[1], sys.argv[2], *map(int, sys.argv[3:])
raylab, embree = ours / 2 / rays, theirs / 3 / rays
print(f'{scene}, {kind}: {rays} rays; instructions a ray: raylab {raylab:.0f}, Embree {embree:.0f} '
      f'(raylab/Embree {raylab / embree:.2f})')
PY
