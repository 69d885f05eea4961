#!/usr/bin/env python3
"""Generate the pair sets (seeded, deterministic).

uniform.jsonl            300 pairs, wi and wo uniform (solid angle) on the upper hemisphere
highlight_FABRIC.jsonl   300 pairs near the specular cones of FABRIC
hard.jsonl               curated hard cases (same for every fabric)
"""
import json
import math

import numpy as np

import ref

DEG = ref.DEG


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def sph(theta_deg, phi_deg):
    t, p = theta_deg * DEG, phi_deg * DEG
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def uniform_hemi(rng):
    z = rng.uniform()
    while z == 0.0:
        z = rng.uniform()
    p = rng.uniform(0, 2 * math.pi)
    r = math.sqrt(max(0.0, 1 - z * z))
    return np.array([r * math.cos(p), r * math.sin(p), z])


def write(path, pairs):
    with open(path, "w") as f:
        for wi, wo in pairs:
            f.write(json.dumps({"wi": [float(x) for x in wi], "wo": [float(x) for x in wo]}) + "\n")


def gen_uniform(n=300, seed=12345):
    rng = np.random.default_rng(seed)
    return [(uniform_hemi(rng), uniform_hemi(rng)) for _ in range(n)]


def jitter(w, rng, sigma_deg=1.0):
    """Rotate w by a small random angle (Gaussian perpendicular offset, sigma ~1 deg)."""
    d = rng.normal(size=3) * sigma_deg * DEG
    d -= (d @ w) * w
    return unit(w + d)


def gen_highlight(fabric, n=300, seed=777):
    """Pairs on (near) the specular cone of a random tangent sample.

    thread j chosen with probability a_j / (a1 + a2); alpha uniform in arc length;
    wi uniform on the upper hemisphere; wo = -(wi.t) t + cos(theta_i) (cos beta e1 + sin beta e2)
    (so wo.t = -wi.t: theta_o = -theta_i) with beta uniform; wo jittered by ~1 deg;
    rejected (whole draw repeated) unless wo.z > 0.
    """
    rng = np.random.default_rng(seed + sum(map(ord, fabric)))
    threads = ref.FABRICS[fabric]
    a = np.array([th["a"] for th in threads])
    pairs = []
    while len(pairs) < n:
        j = rng.choice(2, p=a / a.sum())
        alpha = ref.sample_curve_random(threads[j], rng)
        t0, b = ref.THREAD_AXES[j]
        t = math.cos(alpha) * t0 + math.sin(alpha) * ref.Z
        nn = -math.sin(alpha) * t0 + math.cos(alpha) * ref.Z
        wi = uniform_hemi(rng)
        st = wi @ t
        ct = math.sqrt(max(0.0, 1 - st * st))
        beta = rng.uniform(0, 2 * math.pi)
        wo = -st * t + ct * (math.cos(beta) * nn + math.sin(beta) * b)
        wo = jitter(unit(wo), rng)
        if wo[2] <= 0.0:
            continue
        pairs.append((wi, wo))
    return pairs


def gen_hard():
    eps = 1e-6
    pairs = []
    zz = np.array([0.0, 0.0, 1.0])
    # -- basic: normal, wi = wo, mirror across the normal
    pairs.append((zz, zz))
    for th, ph in [(30, 0), (60, 45), (80, 90), (89, 10)]:
        w = sph(th, ph)
        pairs.append((w, w))
    for th, ph in [(30, 0), (60, 45), (85, 90), (45, 135), (89.9, 30)]:
        w = sph(th, ph)
        pairs.append((w, np.array([-w[0], -w[1], w[2]])))
    # -- near-grazing, z = 1e-6
    gx, gy = unit([1, 0, eps]), unit([0, 1, eps])
    gmx, gmy = unit([-1, 0, eps]), unit([0, -1, eps])
    gd = unit([1, 1, eps * math.sqrt(2)])
    gmd = unit([-1, -1, eps * math.sqrt(2)])
    pairs += [(gx, zz), (gy, zz), (zz, gx), (zz, gy), (gx, gx), (gy, gy),
              (gx, gmx), (gy, gmy), (gx, gy), (gd, gmd), (gd, gd), (gmx, gy)]
    # -- axes tilted to z = 1e-3
    tz = 1e-3
    ax = [unit([1, 0, tz]), unit([-1, 0, tz]), unit([0, 1, tz]), unit([0, -1, tz])]
    other = unit([0.5, 0.3, 0.8])
    for w in ax:
        pairs.append((w, other))
        pairs.append((other, w))
    # -- w parallel to +-t(alpha) at the curve control / end offsets of the fabric table
    #    (the sign with z > 0), for thread 1 (t0 = x) and thread 2 (t0 = y).
    for ad in [5, 18, 25, 30, 32, 35, 50, 55]:
        c, s = math.cos(ad * DEG), math.sin(ad * DEG)
        for k, (wp, wm) in enumerate([(np.array([c, 0, s]), np.array([-c, 0, s])),
                                      (np.array([0, c, s]), np.array([0, -c, s]))]):
            # wp = t(+ad), wm = -t(-ad); partner: the normal, the other sign, or mirror
            pairs.append((wp, zz) if k == 0 else (zz, wp))
            pairs.append((wp, wm) if ad % 2 else (wm, wp))
    # alpha = +-90: t = +-z ; alpha = 0: t = t0 lies in the horizon, tilt to z = 1e-6
    pairs.append((zz, sph(40, 20)))
    pairs.append((unit([1, 0, eps]), unit([-1, 0, eps * 3])))
    # -- below / on the horizon: must give exactly 0
    pairs += [(np.array([1.0, 0, 0]), zz), (zz, np.array([0, 1.0, 0])),
              (unit([0.3, 0.2, -0.5]), zz), (zz, unit([0.1, 0.2, -1e-9]))]
    return pairs


if __name__ == "__main__":
    write("uniform.jsonl", gen_uniform())
    write("hard.jsonl", gen_hard())
    for fab in ref.FABRIC_NAMES:
        write("highlight_%s.jsonl" % fab, gen_highlight(fab))
    print("hard pairs:", len(gen_hard()))
