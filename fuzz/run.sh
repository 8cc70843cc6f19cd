#!/usr/bin/env bash
# Runs relief's fuzz targets, each for SECONDS (default 600), from the project's root:
#   fuzz/run.sh [SECONDS] [TARGET...]
# Needs cargo-fuzz (cargo install cargo-fuzz). The stable toolchain builds it with
# RUSTC_BOOTSTRAP=1. New crashes land in fuzz/artifacts/TARGET/; copy each into
# crates/relief-io/tests/fuzz_regressions/TARGET/ so the test suite replays it forever.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(npy npz geotiff hgt asc png mlhm_scene mlhm_native stacks_native)
for target in "${targets[@]}"; do
  case $target in
    geotiff) max_len=200000 ;;
    hgt) max_len=2884802 ;;
    mlhm_scene) max_len=65536 ;;
    *) max_len=8192 ;;
  esac
  mkdir -p "fuzz/corpus/$target"
  echo "== $target: ${seconds}s"
  RUSTC_BOOTSTRAP=1 cargo fuzz run -O "$target" "fuzz/corpus/$target" "fuzz/seeds/$target" -- \
    -max_total_time="$seconds" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
done
