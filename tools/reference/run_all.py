#!/usr/bin/env python3
"""Write ref_FABRIC_{uniform,highlight,hard}.jsonl (65536 samples/thread) and report
convergence against 16384 (and 262144) samples per thread."""
import json
import sys
from multiprocessing import Pool

import numpy as np

import ref


def load(path):
    with open(path) as f:
        return [json.loads(l) for l in f if l.strip()]


def job(args):
    fab, kind = args
    path = "uniform.jsonl" if kind == "uniform" else (
        "hard.jsonl" if kind == "hard" else "highlight_%s.jsonl" % fab)
    pairs = load(path)
    out = {}
    for n in (16384, 65536, 262144):
        out[n] = np.array([ref.F(fab, p["wi"], p["wo"], n) for p in pairs])
    with open("ref_%s_%s.jsonl" % (fab, kind), "w") as f:
        for v in out[65536]:
            f.write(json.dumps({"f": [float(x) for x in v]}) + "\n")
    return fab, kind, out


def stats(a, b, floor):
    """max relative difference over entries with |b| > floor, and max abs diff."""
    m = np.abs(b) > floor
    rel = np.max(np.abs(a - b)[m] / np.abs(b)[m]) if m.any() else 0.0
    return rel, np.max(np.abs(a - b))


if __name__ == "__main__":
    jobs = [(f, k) for f in ref.FABRIC_NAMES for k in ("uniform", "highlight", "hard")]
    with Pool(2) as p:
        res = p.map(job, jobs)
    print("%-32s %-9s | %-23s | %-23s | %s" % ("fabric", "set", "16k vs 64k rel / abs",
                                            "64k vs 256k rel / abs", "max F"))
    worst = [0, 0]
    for fab, kind, out in res:
        assert all(np.isfinite(v).all() for v in out.values())
        r1, a1 = stats(out[16384], out[65536], 1e-12)
        r2, a2 = stats(out[65536], out[262144], 1e-12)
        worst = [max(worst[0], r1), max(worst[1], r2)]
        print("%-32s %-9s | %10.2e / %10.2e | %10.2e / %10.2e | %.4g"
              % (fab, kind, r1, a1, r2, a2, out[65536].max()))
    print("worst rel diff 16k vs 64k: %.3e   64k vs 256k: %.3e" % tuple(worst))
