#!/usr/bin/env bash
# GPU cost of the lookup shader against the paper-mode shader and the resonant
# shader at 1024×1024, every built-in fabric (or those named in FABRICS, space separated),
# on whatever adapter wgpu finds: the median ms per frame that `clothbake render` prints for
# --evaluator constant (F = 1/π: the frame without BRDF work, the floor under every shader),
# table (the lookup), paper:8, paper:32, and resonant (default nodes), in one run. A shared
# machine's speed drifts over minutes, so the five renders of a fabric alternate, ROUNDS
# times (default 3), and each figure is the median of its rounds' medians of FRAMES frames
# (default 5). Ratios: whole frames, and BRDF work alone (frame − floor). The scene's lights
# only (--env none): the environment light is measured by examples/environment_front.rs.
# Needs the default tables (clothbake bake). With ALT_TABLES=DIR (tables of another layout,
# e.g. `clothbake bake --layout split_frame --out DIR`), the lookup from those tables is
# rendered in the same rounds and reported in three more columns. Prints a Markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=target/release/clothbake
frames=${FRAMES:-5}
rounds=${ROUNDS:-3}
fabrics=${FABRICS:-$("$bin" fabrics | awk '/^[a-z]/ {print $1}')}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

median_ms() { # the ms figure of the render command's "median X ms per frame" line
    "$bin" render --width 1024 --height 1024 --frames "$frames" --out "$out/frame.png" --env none "$@" |
        tee -a "$out/log" | sed -n 's/.*median \([0-9.]*\) ms per frame.*/\1/p'
}

"$bin" render --width 64 --height 64 --frames 1 --out "$out/probe.png" \
    --fabric "$(awk '{print $1}' <<<"${fabrics//$'\n'/ }")" | grep '^adapter'
echo
alt=${ALT_TABLES:-}
alt_header=""
alt_rule=""
if [[ -n $alt ]]; then
    alt_header=" lookup ($alt) ms | BRDF work: N = 32 / lookup ($alt) | BRDF work: resonant / lookup ($alt) |"
    alt_rule="---:|---:|---:|"
fi
echo "| fabric | floor ms | lookup ms | paper N = 8 ms | paper N = 32 ms | resonant ms | N = 8 / lookup | N = 32 / lookup | resonant / lookup | BRDF work: N = 32 / lookup | BRDF work: resonant / lookup |$alt_header"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|$alt_rule"
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

for fabric in $fabrics; do
    declare -A ms=()
    for ((round = 0; round < rounds; round++)); do
        ms[floor]+="$(median_ms --fabric "$fabric" --evaluator constant) "
        ms[lookup]+="$(median_ms --fabric "$fabric") "
        ms[n8]+="$(median_ms --fabric "$fabric" --evaluator paper:8) "
        ms[n32]+="$(median_ms --fabric "$fabric" --evaluator paper:32) "
        ms[resonant]+="$(median_ms --fabric "$fabric" --evaluator resonant) "
        if [[ -n $alt ]]; then
            ms[alt]+="$(median_ms --fabric "$fabric" --tables "$alt") "
        fi
    done
    keys="floor lookup n8 n32 resonant"
    [[ -n $alt ]] && keys+=" alt"
    for key in $keys; do
        ms[$key]=$(tr ' ' '\n' <<<"${ms[$key]}" | grep . | median)
    done
    awk -v f="$fabric" -v z="${ms[floor]}" -v l="${ms[lookup]}" -v a="${ms[n8]}" -v b="${ms[n32]}" \
        -v r="${ms[resonant]}" -v x="${ms[alt]:-}" 'BEGIN {
        printf "| %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.2f× | %.2f× | %.2f× | %.2f× | %.2f× |",
            f, z, l, a, b, r, a / l, b / l, r / l, (b - z) / (l - z), (r - z) / (l - z)
        if (x != "") printf " %.0f | %.2f× | %.2f× |", x, (b - z) / (x - z), (r - z) / (x - z)
        printf "\n" }'
    unset ms
done
