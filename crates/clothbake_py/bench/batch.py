"""Python's batch evaluation against the Rust batch it wraps, side by side in one run.

    .venv/bin/python crates/clothbake_py/bench/batch.py [PAIRS] [EVALUATOR]

For each built-in fabric, PAIRS random pairs (default 1,000,000) of directions above the
horizon and the evaluator (default `table`, each fabric's table in tables/: run the bake
first): the median of 7 calls of `Evaluator.eval` on NumPy arrays (reading and normalising
the arrays, the batch, the result array) and the median of 7 runs of the same Rust batch
(`FabricEvaluator::eval_batch`) on pairs already in Rust's form, per pair, and their ratio.
"""

import statistics
import sys
import time

import numpy as np

import clothbake

REPEATS = 7


def hemisphere(rng, n):
    w = rng.normal(size=(n, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    w[:, 2] = np.abs(w[:, 2])
    return w


def main():
    pairs = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    spelling = sys.argv[2] if len(sys.argv) > 2 else "table"
    rng = np.random.default_rng(7)
    wi, wo = hemisphere(rng, pairs), hemisphere(rng, pairs)
    print(f"{pairs:,} pairs, evaluator {spelling}, median of {REPEATS}\n")
    print("| fabric | Python `eval` | Rust batch | ratio |")
    print("|---|---:|---:|---:|")
    for name in clothbake.fabric_names():
        evaluator = clothbake.Evaluator(clothbake.Fabric.builtin(name), spelling)
        python, rust = [], []
        for _ in range(REPEATS):
            start = time.perf_counter()
            evaluator.eval(wi, wo)
            python.append(time.perf_counter() - start)
            rust.append(evaluator._rust_batch_seconds(wi, wo))
        p, r = statistics.median(python), statistics.median(rust)
        print(f"| {name} | {1e9 * p / pairs:.0f} ns | {1e9 * r / pairs:.0f} ns | {p / r:.2f} |")


if __name__ == "__main__":
    main()
