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
modes = ["direct", "paper_n32", "paper_n8", "table_lookup"]
print("| fabric | " + " | ".join(f"{m} (ns/eval)" for m in modes) + " | direct / lookup |")
print("|---|" + "---:|" * (len(modes) + 1))
for fabric, by_mode in rows.items():
    cells = [f"{by_mode[m]:,.0f}" if m in by_mode else "–" for m in modes]
    ratio = by_mode["direct"] / by_mode["table_lookup"] if "table_lookup" in by_mode else float("nan")
    print(f"| {fabric} | " + " | ".join(cells) + f" | {ratio:,.0f}× |")
