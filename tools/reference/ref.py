#!/usr/bin/env python3
"""Independent reference implementation of the microcylinder cloth model
(Sadeghi et al. 2013) exactly as specified in the physics contract (restated in docs/model.md) (defaults only).

F(fabric_name, wi, wo) -> RGB cosine-weighted patch transfer (direct evaluation).

CLI:  python3 ref.py FABRIC [--n N] < pairs.jsonl     (lines {"wi":[x,y,z],"wo":[x,y,z]})
      prints {"f":[r,g,b]} per line.

Frames: x = thread 1 direction, y = thread 2 direction, z = normal.
Thread 1: t0 = x, b = y.   Thread 2: t0 = y, b = x.
t(a) = cos a t0 + sin a z,  n(a) = -sin a t0 + cos a z.

Per sample, every direction w is decomposed in the orthonormal frame (t, n, b):
    w = (w.t) t + (w.n) n + (w.b) b
so that, exactly (no cancellation when w is close to t):
    sin th = w.t,   cos th = |w_perp| = sqrt((w.n)^2 + (w.b)^2)
    w_perp = ((w.n) n + (w.b) b)/cos th          -> cos phi = (w.n)/cos th
    w_par  = ((w.t) t + (w.n) n)/|w_par|, |w_par| = sqrt((w.t)^2 + (w.n)^2)
                                                 -> cos psi = (w.n)/|w_par|
    wi_perp.wo_perp = ((wi.n)(wo.n) + (wi.b)(wo.b)) / (cos th_i cos th_o)
    wi_par.wo_par   = ((wi.t)(wo.t) + (wi.n)(wo.n)) / (|wi_par| |wo_par|)
(`sample_literal` below recomputes the same things with literal vector
projections, as a cross-check.)
"""
import json
import math
import sys

import numpy as np

DEG = math.pi / 180.0
SIGMA_U = 20.0 * DEG          # u(x) = exp(-x^2 / (2 sigma_u^2)), unit height
DEGENERATE_EPS = 1e-12        # projection norm <= this  ->  degenerate projection
N_DEFAULT = 65536             # samples per thread for the reference outputs

X = np.array([1.0, 0.0, 0.0])
Y = np.array([0.0, 1.0, 0.0])
Z = np.array([0.0, 0.0, 1.0])


def _thread(eta, scale, rgb, kd, gs, gv, a, offsets, lengths):
    return dict(eta=eta, A=scale * np.array(rgb, dtype=float), kd=kd,
                gamma_s=gs * DEG, gamma_v=gv * DEG, a=a,
                offsets=[o * DEG for o in offsets], lengths=list(lengths))


# The paper's measured set, fabric table of docs/model.md (angles in degrees, A = scale x RGB).
FABRICS = {
    "linen_plain": [
        _thread(1.46, 0.3, (0.2, 0.8, 1.0), 0.3, 12, 24, 0.33, (-25, 25), (1,)),
        _thread(1.46, 0.3, (0.2, 0.8, 1.0), 0.3, 12, 24, 0.33, (-25, 25), (1,)),
    ],
    "silk_crepe_de_chine": [
        _thread(1.345, 0.12, (1.0, 0.95, 0.05), 0.2, 5, 10, 0.75,
                (-35, -35, 35, 35), (1, 1, 1)),
        _thread(1.345, 0.16, (1.0, 0.95, 0.05), 0.3, 18, 32, 0.25, (0, 0), (1,)),
    ],
    "polyester_satin_charmeuse": [
        _thread(1.539, 0.035, (1.0, 0.37, 0.3), 0.1, 2.5, 5, 0.9,
                (-32, -32, -18, 0, 0, 18, 32, 32),
                (1.33, 0.66, 2, 2, 2, 0.66, 1.33)),
        _thread(1.539, 0.2, (1.0, 0.37, 0.3), 0.7, 30, 60, 0.1, (0, 0), (1,)),
    ],
    "polyester_satin_charmeuse_back": [
        _thread(1.539, 0.035, (1.0, 0.37, 0.3), 0.1, 2.5, 5, 0.67,
                (-30, -30, 30, 30, -5, -5, 5, 5),
                (1.33, 1.33, 1.33, 0, 0.67, 0.67, 0.67)),
        _thread(1.539, 0.2, (1.0, 0.37, 0.3), 0.7, 30, 60, 0.33, (0, 0), (3,)),
    ],
    "silk_shot": [
        _thread(1.345, 0.2, (0.1, 1.0, 0.4), 0.1, 4, 8, 0.86,
                (-25, -25, 25, 25), (1.33, 2.67, 1.33)),
        _thread(1.345, 0.6, (1.0, 0.0, 0.1), 0.1, 5, 10, 0.14, (0, 0), (1,)),
    ],
    "velvet": [
        _thread(1.46, 0.3, (0.05, 0.02, 0.0), 0.1, 6, 12, 0.5, (-90, -50), (1,)),
        _thread(1.46, 0.3, (0.05, 0.02, 0.0), 0.1, 6, 12, 0.5,
                (-90, -55, 55, 90), (0.5, 0, 0.5)),
    ],
}
FABRIC_NAMES = list(FABRICS)

# (t0, b) per thread index
THREAD_AXES = [(X, Y), (Y, X)]


# ----------------------------------------------------------------------------
# Curve sampling: composite midpoint rule, uniform in arc length.
# ----------------------------------------------------------------------------
def kink_offsets(j, ws):
    """Offsets alpha in (-pi/2, pi/2) where w.n(alpha) = 0 for some w in ws.

    There cos(phi) and cos(psi) change sign (the kinks of max(., 0) in M and P),
    and when w is also (nearly) normal to b this is where w is (nearly) parallel
    to +-t(alpha): the integrand has a spike there as narrow as w's tilt out of
    the t0-z plane (e.g. grazing wi ~ +x, wo ~ -x).  Splitting the curve at these
    offsets lets the quadrature resolve that spike.
    """
    t0, _ = THREAD_AXES[j]
    out = []
    for w in ws:
        w_t0, w_z = float(w @ t0), float(w @ Z)
        if w_t0 != 0.0:
            out.append(math.atan(w_z / w_t0))   # -sin a w_t0 + cos a w_z = 0
    return out


def curve_samples(thread, n_total, breaks=()):
    """Return (alpha[rad], weight) with weights summing to 1.

    Segment k joins offsets[k] -> offsets[k+1] and has relative length
    lengths[k].  Zero-length segments (jumps) hold no samples.  A segment with
    equal end offsets is a constant-alpha segment that still holds samples in
    proportion to its length.  A single-segment thread ignores its length.
    Each segment with length l_k > 0 gets n_k = max(1, round(n_total l_k / L))
    midpoints; each midpoint weighs l_k / (L n_k), so the segment weights are
    exact whatever the rounding.

    `breaks`: offsets at which non-constant segments are additionally split;
    a piece covering fraction f of its segment gets
    max(n_total // 64, round(n_k f)) midpoints of weight (l_k / L) f / count.
    Still the composite midpoint rule, uniform in arc length inside each piece.
    """
    offs = thread["offsets"]
    lens = thread["lengths"]
    assert len(lens) == len(offs) - 1 and len(offs) >= 2
    if len(lens) == 1:
        lens = [1.0]
    L = float(sum(lens))
    assert L > 0
    n_min_piece = max(1, n_total // 64)
    alphas, weights = [], []
    for k, l in enumerate(lens):
        if l <= 0:
            continue
        nk = max(1, int(round(n_total * l / L)))
        a0, a1 = offs[k], offs[k + 1]
        # split points as fractions of the segment, strictly inside it
        cuts = [0.0, 1.0]
        if a1 != a0:
            cuts += [(bk - a0) / (a1 - a0) for bk in breaks
                     if 0.0 < (bk - a0) / (a1 - a0) < 1.0]
        cuts = sorted(set(cuts))
        for c0, c1 in zip(cuts[:-1], cuts[1:]):
            f = c1 - c0
            if len(cuts) == 2:
                m = nk
            else:
                m = max(n_min_piece, int(round(nk * f)))
            u = c0 + f * (np.arange(m) + 0.5) / m
            alphas.append(a0 + (a1 - a0) * u)
            weights.append(np.full(m, (l / L) * f / m))
    return np.concatenate(alphas), np.concatenate(weights)


def sample_curve_random(thread, rng):
    """One alpha drawn uniformly in arc length along the thread's curve."""
    offs = thread["offsets"]
    lens = np.array(thread["lengths"] if len(thread["lengths"]) > 1 else [1.0], float)
    k = rng.choice(len(lens), p=lens / lens.sum())
    return offs[k] + (offs[k + 1] - offs[k]) * rng.uniform()


# ----------------------------------------------------------------------------
# Scalar ingredients
# ----------------------------------------------------------------------------
def fresnel_dielectric(cos_i, eta):
    """Exact unpolarised Fresnel reflectance, air (n=1) -> index eta."""
    c = np.clip(cos_i, 0.0, 1.0)
    if eta == 1.0:
        return np.zeros_like(c)
    sin2_t = (1.0 - c * c) / (eta * eta)
    tir = sin2_t >= 1.0                       # impossible for eta > 1
    cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2_t))
    rs = (c - eta * cos_t) / (c + eta * cos_t)
    rp = (eta * c - cos_t) / (eta * c + cos_t)
    return np.where(tir, 1.0, 0.5 * (rs * rs + rp * rp))


def gauss(gamma, x):
    """Unit-area Gaussian, gamma = standard deviation (radians)."""
    return np.exp(-x * x / (2.0 * gamma * gamma)) / (gamma * math.sqrt(2.0 * math.pi))


def u_fn(x):
    """Unit-height Gaussian, sigma_u = 20 deg."""
    return np.exp(-x * x / (2.0 * SIGMA_U * SIGMA_U))


# ----------------------------------------------------------------------------
# One thread: per-sample contribution s (N,3) and P (N,)
# ----------------------------------------------------------------------------
def thread_samples(thread, j, wi, wo, alpha):
    """s and P for thread index j (0 or 1) at tangent offsets alpha (array)."""
    t0, b = THREAD_AXES[j]
    ca, sa = np.cos(alpha), np.sin(alpha)

    def coords(w):
        w_t0, w_z, w_b = float(w @ t0), float(w @ Z), float(w @ b)
        wt = ca * w_t0 + sa * w_z            # w.t
        wn = -sa * w_t0 + ca * w_z           # w.n
        return wt, wn, w_b

    ti, ni, bi = coords(wi)
    to, no, bo = coords(wo)

    cos_ti = np.hypot(ni, bi)                # |wi_perp| = cos(theta_i)
    cos_to = np.hypot(no, bo)
    par_i = np.hypot(ti, ni)                 # |wi_par|
    par_o = np.hypot(to, no)

    degen = ((cos_ti <= DEGENERATE_EPS) | (cos_to <= DEGENERATE_EPS)
             | (par_i <= DEGENERATE_EPS) | (par_o <= DEGENERATE_EPS))
    # safe denominators (degenerate samples are zeroed at the end)
    cti = np.where(degen, 1.0, cos_ti)
    cto = np.where(degen, 1.0, cos_to)
    pi_ = np.where(degen, 1.0, par_i)
    po_ = np.where(degen, 1.0, par_o)

    theta_i = np.arctan2(ti, cos_ti)         # in [-pi/2, pi/2]
    theta_o = np.arctan2(to, cos_to)
    theta_h = 0.5 * (theta_i + theta_o)
    theta_d = 0.5 * (theta_i - theta_o)

    cos_phi_i = ni / cti
    cos_phi_o = no / cto
    cos_phid = np.clip((ni * no + bi * bo) / (cti * cto), -1.0, 1.0)
    phi_d = np.arccos(cos_phid)

    cos_psi_i = ni / pi_
    cos_psi_o = no / po_
    cos_psid = np.clip((ti * to + ni * no) / (pi_ * po_), -1.0, 1.0)
    psi_d = np.arccos(cos_psid)

    # thread scattering function f_s
    cos_half_phid = np.cos(0.5 * phi_d)
    cos_td = np.cos(theta_d)
    cos_td2 = np.where(degen, 1.0, cos_td * cos_td)
    Fr = fresnel_dielectric(cos_td * cos_half_phid, thread["eta"])
    Ft = (1.0 - Fr) ** 2
    surf = Fr * cos_half_phid * gauss(thread["gamma_s"], theta_h)            # (N,)
    kd = thread["kd"]
    vol = Ft * ((1.0 - kd) * gauss(thread["gamma_v"], theta_h) + kd) / (cti + cto)  # (N,)
    fs = (surf[:, None] + vol[:, None] * thread["A"][None, :]) / cos_td2[:, None]

    # shadowing / masking and reweighting
    Mi, Mo = np.maximum(cos_phi_i, 0.0), np.maximum(cos_phi_o, 0.0)
    Pi, Po = np.maximum(cos_psi_i, 0.0), np.maximum(cos_psi_o, 0.0)
    uphi, upsi = u_fn(phi_d), u_fn(psi_d)
    M = (1.0 - uphi) * Mi * Mo + uphi * np.minimum(Mi, Mo)
    P = (1.0 - upsi) * Pi * Po + upsi * np.minimum(Pi, Po)

    s = fs * (M * P * cos_ti)[:, None]
    s[degen] = 0.0
    P = np.where(degen, 0.0, P)
    return s, P


def sample_literal(thread, j, wi, wo, alpha):
    """Slow single-sample version with literal vector projections (cross-check)."""
    t0, b = THREAD_AXES[j]
    t = math.cos(alpha) * t0 + math.sin(alpha) * Z
    n = -math.sin(alpha) * t0 + math.cos(alpha) * Z

    def ang(w):
        st = float(w @ t)
        ct = math.sqrt(max(0.0, 1.0 - st * st))
        wp = w - st * t
        wpar = w - float(w @ b) * b
        if np.linalg.norm(wp) <= DEGENERATE_EPS or np.linalg.norm(wpar) <= DEGENERATE_EPS:
            return None
        wp = wp / np.linalg.norm(wp)
        wpar = wpar / np.linalg.norm(wpar)
        return math.asin(max(-1.0, min(1.0, st))), ct, wp, wpar, float(wp @ n), float(wpar @ n)

    ai, ao = ang(wi), ang(wo)
    if ai is None or ao is None:
        return np.zeros(3), 0.0
    thi, cti, wpi, wai, cphi_i, cpsi_i = ai
    tho, cto, wpo, wao, cphi_o, cpsi_o = ao
    th, td = (thi + tho) / 2, (thi - tho) / 2
    phid = math.acos(max(-1.0, min(1.0, float(wpi @ wpo))))
    psid = math.acos(max(-1.0, min(1.0, float(wai @ wao))))
    Fr = float(fresnel_dielectric(np.array(math.cos(td) * math.cos(phid / 2)), thread["eta"]))
    Ft = (1 - Fr) ** 2
    kd = thread["kd"]
    fs = (Fr * math.cos(phid / 2) * float(gauss(thread["gamma_s"], th))
          + Ft * ((1 - kd) * float(gauss(thread["gamma_v"], th)) + kd) / (cti + cto) * thread["A"]
          ) / math.cos(td) ** 2
    u1, u2 = float(u_fn(phid)), float(u_fn(psid))
    Mi, Mo = max(cphi_i, 0), max(cphi_o, 0)
    Pi, Po = max(cpsi_i, 0), max(cpsi_o, 0)
    M = (1 - u1) * Mi * Mo + u1 * min(Mi, Mo)
    P = (1 - u2) * Pi * Po + u2 * min(Pi, Po)
    return fs * M * P * cti, P


# ----------------------------------------------------------------------------
# Patch
# ----------------------------------------------------------------------------
def F(fabric_name, wi, wo, n=N_DEFAULT):
    """Direct evaluation of F(wi, wo) (RGB numpy array). wi, wo are normalised."""
    wi = np.asarray(wi, float)
    wo = np.asarray(wo, float)
    wi = wi / np.linalg.norm(wi)
    wo = wo / np.linalg.norm(wo)
    if wi[2] <= 0.0 or wo[2] <= 0.0:
        return np.zeros(3)
    threads = FABRICS[fabric_name]
    num = np.zeros(3)
    Q = 0.0
    for j, th in enumerate(threads):
        alpha, wgt = curve_samples(th, n, kink_offsets(j, (wi, wo)))
        s, P = thread_samples(th, j, wi, wo, alpha)
        num += th["a"] * (wgt @ s)
        Q += th["a"] * float(wgt @ P)
    a_sum = threads[0]["a"] + threads[1]["a"]
    Q += (1.0 - a_sum) * max(wo[2], 0.0)
    if Q == 0.0:
        return np.zeros(3)
    return num / Q


def main(argv):
    if len(argv) < 2 or argv[1] not in FABRICS:
        sys.stderr.write("usage: ref.py FABRIC [--n N] < pairs.jsonl\n  fabrics: %s\n"
                         % ", ".join(FABRIC_NAMES))
        return 2
    n = N_DEFAULT
    if "--n" in argv:
        n = int(argv[argv.index("--n") + 1])
    for line in sys.stdin:
        line = line.strip()
        if not line:
            continue
        d = json.loads(line)
        f = F(argv[1], d["wi"], d["wo"], n)
        print(json.dumps({"f": [float(v) for v in f]}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
