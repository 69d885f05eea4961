#!/usr/bin/env python3
"""Prints criterion's medians as Markdown tables: the `eval` group in nanoseconds per
evaluation (each criterion iteration evaluates a batch of 256 pairs), and the `bake` group
in texels per second.

Usage: cargo bench && python3 scripts/bench-table.py
"""
import json
import pathlib

BATCH = 256


def medians(group):
    """{fabric: {benchmark: (median ns per iteration, throughput elements or None)}}"""
    rows = {}
    for estimates in sorted(pathlib.Path("target/criterion", group).glob("*/*/new/estimates.json")):
        name, fabric = estimates.parts[-4], estimates.parts[-3]
        median_ns = json.loads(estimates.read_text())["median"]["point_estimate"]
        benchmark = json.loads((estimates.parent / "benchmark.json").read_text())
        elements = (benchmark.get("throughput") or {}).get("Elements")
        rows.setdefault(fabric, {})[name] = (median_ns, elements)
    return rows


evaluations = ["direct", "paper_n1024", "paper_n128", "paper_n32", "paper_n8", "resonant_default"]
eval_rows = medians("eval")
# Every lookup benchmark measured (lookup_<kind>_<layout>), default layout first.
lookups = sorted({name for by_mode in eval_rows.values() for name in by_mode
                  if name.startswith("lookup_")},
                 key=lambda n: ("grid4d" in n, n))
modes = evaluations + lookups
FAST = "lookup_batch_thread_frame"  # the fast CPU path (eight pairs per SIMD step)


def ratio(ns, a, b):
    return f"{ns[a] / ns[b]:,.1f}×" if {a, b} <= ns.keys() else "–"


print("| fabric | " + " | ".join(f"{m} (ns/eval)" for m in modes)
      + f" | resonant / {FAST} | paper_n128 / resonant | paper_n1024 / resonant |")
print("|---|" + "---:|" * (len(modes) + 3))
for fabric, by_mode in eval_rows.items():
    ns = {m: v[0] / BATCH for m, v in by_mode.items()}
    cells = [f"{ns[m]:,.1f}" if m in ns and ns[m] < 100 else f"{ns[m]:,.0f}" if m in ns else "–"
             for m in modes]
    print(f"| {fabric} | " + " | ".join(cells) + f" | {ratio(ns, 'resonant_default', FAST)} | "
          f"{ratio(ns, 'paper_n128', 'resonant_default')} | {ratio(ns, 'paper_n1024', 'resonant_default')} |")

bake = medians("bake")
if bake:
    layouts = sorted({name for by_layout in bake.values() for name in by_layout})
    print()
    print("| fabric | " + " | ".join(f"bake {l} (texels/s)" for l in layouts) + " |")
    print("|---|" + "---:|" * len(layouts))
    for fabric, by_layout in bake.items():
        cells = []
        for l in layouts:
            if l in by_layout and by_layout[l][1]:
                ns, texels = by_layout[l]
                cells.append(f"{texels / (ns * 1e-9):,.0f}")
            else:
                cells.append("–")
        print(f"| {fabric} | " + " | ".join(cells) + " |")
