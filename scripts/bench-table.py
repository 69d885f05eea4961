#!/usr/bin/env python3
"""Prints criterion's medians for the `eval` group as a Markdown table, nanoseconds per
evaluation (each criterion iteration evaluates a batch of 256 pairs).

Usage: cargo bench --bench direct_eval && python3 scripts/bench-table.py
"""
import json
import pathlib

BATCH = 256
root = pathlib.Path("target/criterion/eval")
rows = {}
for estimates in sorted(root.glob("*/*/new/estimates.json")):
    mode, fabric = estimates.parts[-4], estimates.parts[-3]
    median_ns = json.loads(estimates.read_text())["median"]["point_estimate"] / BATCH
    rows.setdefault(fabric, {})[mode] = median_ns
modes = ["direct", "paper_n32", "paper_n8"]
print("| fabric | " + " | ".join(f"{m} (ns/eval)" for m in modes) + " | direct / paper_n32 |")
print("|---|" + "---:|" * (len(modes) + 1))
for fabric, by_mode in rows.items():
    cells = [f"{by_mode[m]:,.0f}" for m in modes]
    print(f"| {fabric} | " + " | ".join(cells) + f" | {by_mode['direct'] / by_mode['paper_n32']:.0f}× |")
