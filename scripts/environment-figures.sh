#!/usr/bin/env bash
# The environment light, every built-in fabric (or those named in FABRICS), on whatever
# adapter wgpu finds, with the default tables (clothbake bake):
# - image error of `render --env default --no-lights` against its CPU reference (F by the
#   resonant quadrature, the environment by 256 multiple-importance samples per pixel) at
#   K = 16, 64 and 256 filtered importance samples per pixel, 128² frames;
# - the median ms per frame at 1024² of the default scene with its lights only (--env
#   none) and with the environment at each K (FRAMES frames, default 3).
# Prints two Markdown tables.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/clothbake
frames=${FRAMES:-3}
fabrics=${FABRICS:-$("$bin" fabrics | awk '/^[a-z]/ {print $1}')}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

error_pct() { # fabric, K
    "$bin" render --fabric "$1" --width 128 --height 128 --frames 1 --out "$out/e.png" \
        --env default --no-lights --env-samples "$2" --reference --reference-samples 256 |
        sed -n 's/.*relative L2 \([0-9.]*\)%.*/\1/p'
}
median_ms() { # fabric, render options
    local fabric=$1
    shift
    "$bin" render --fabric "$fabric" --width 1024 --height 1024 --frames "$frames" \
        --out "$out/f.png" "$@" | sed -n 's/.*median \([0-9.]*\) ms per frame.*/\1/p'
}

"$bin" render --width 64 --height 64 --frames 1 --out "$out/probe.png" --env none \
    --fabric "$(awk '{print $1}' <<<"${fabrics//$'\n'/ }")" | grep '^adapter'
echo
echo "| fabric | K = 16 | K = 64 | K = 256 |"
echo "|---|---:|---:|---:|"
for fabric in $fabrics; do
    echo "| $fabric | $(error_pct "$fabric" 16)% | $(error_pct "$fabric" 64)% | $(error_pct "$fabric" 256)% |"
done
echo
echo "| fabric | lights only | + environment K = 16 | K = 64 | K = 256 |"
echo "|---|---:|---:|---:|---:|"
for fabric in $fabrics; do
    echo "| $fabric | $(median_ms "$fabric" --env none) ms | $(median_ms "$fabric" --env-samples 16) ms | $(median_ms "$fabric" --env-samples 64) ms | $(median_ms "$fabric" --env-samples 256) ms |"
done
