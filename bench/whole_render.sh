#!/bin/bash
# The whole `relief render` of a terrain, as docs/performance.md counts it: for each binary
# given, with and without shadows, the fastest of three wall times (seconds) at 192x108 and at
# 1920x1080; the difference is what the 1920x1080 frame's extra rays cost.
#
#   IN=fbm-4096.npy bench/whole_render.sh target/release/relief [OTHER_BINARY...]
set -eu
IN=${IN:?set IN to a terrain, e.g. IN=fbm-4096.npy}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
for shadows in off on; do
  flag=""; [ "$shadows" = off ] && flag="--no-shadows"
  for binary in "$@"; do
    for size in 192x108 1920x1080; do
      times=""
      for _ in 1 2 3; do
        start=$(date +%s.%N)
        "$binary" render "$IN" --size "$size" $flag -o "$OUT/picture.png" >/dev/null 2>&1
        times="$times $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')"
      done
      fastest=$(printf '%s\n' $times | sort -g | head -1)
      echo "$binary shadows $shadows $size: fastest $fastest s ($times )"
    done
  done
done
