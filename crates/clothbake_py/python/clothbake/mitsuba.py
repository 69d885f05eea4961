"""The ``clothbake`` BSDF for Mitsuba 3: a fabric of the Sadeghi et al. 2013 model, by a
baked table or any other evaluator of clothbake's registry, sampled by clothbake's sampler.

Importing this module registers the plugin (``mi.register_bsdf``) in the current variant;
set a variant first (``llvm_ad_rgb`` or ``scalar_rgb``)::

    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    import clothbake.mitsuba
    bsdf = mi.load_dict({"type": "clothbake", "fabric": "velvet", "table": "tables/velvet.exr"})

Parameters: ``fabric`` (a built-in fabric, or one of ``fabrics``), ``fabrics`` (a fabric file,
TOML), ``table`` (a baked table: the evaluator is then ``table:TABLE``) or ``evaluator`` (any
spelling: ``direct``, ``paper:32``, ``resonant``, ``table:PATH``; default ``direct`` without a
table).

Frames: Mitsuba's shading frame is clothbake's cloth frame as it is, thread 1 along the
shading tangent (``dp/du``, the mesh's UV u), thread 2 along the bitangent, z the shading
normal. clothbake's F(wi = light, wo = view) holds every cosine, so it is Mitsuba's
``eval(si.wi = view, wo = light)`` unchanged. The cloth is two-sided as clothbake's runtime
draws it: seen from below, both directions are mirrored into the upper hemisphere of the frame
whose normal faces the viewer, (x, y, z) -> (x, -y, -z) (the tangent kept, the normal and
bitangent turned).

The evaluation runs in clothbake's Rust batch over the whole wavefront: the Dr.Jit arrays are
evaluated, passed through NumPy and read back, so the plugin suits Mitsuba's evaluated mode
(``dr.set_flag(dr.JitFlag.SymbolicLoops, False)`` and ``SymbolicCalls``, False, for a path
tracer; ``mitsuba.chi2`` needs nothing).
"""

import drjit as dr
import mitsuba as mi
import numpy as np

from ._clothbake import ClothbakeError, Evaluator, Fabric, load_fabrics

_FLAGS = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide


def _string(props, name, default=""):
    return props[name] if props.has_property(name) else default


def _fabric(props):
    name = _string(props, "fabric")
    if not name:
        raise ClothbakeError("clothbake BSDF: the parameter 'fabric' is missing")
    path = _string(props, "fabrics")
    if not path:
        return Fabric.builtin(name)
    for fabric in load_fabrics(path):
        if fabric.name == name:
            return fabric
    raise ClothbakeError(f"clothbake BSDF: fabric '{name}' is not in {path}")


_MIRROR = np.array([1.0, -1.0, -1.0])


def _rows(vector, n):
    """A Dr.Jit Vector3f as an (n, 3) float64 array (a literal of width 1 repeated)."""
    rows = np.asarray(vector.numpy(), dtype=np.float64).T.reshape(-1, 3)
    return np.array(np.broadcast_to(rows, (n, 3)))


def _pair(si_wi, wo, n=1):
    """The view and light directions as (N, 3) arrays in clothbake's terms, N the widest of
    them and n. Rows whose view is below the surface are mirrored into the hemisphere the
    viewer is in, (x, y, z) -> (x, -y, -z) (two-sided cloth; `below` marks them). Dr.Jit
    pads lanes it does not use with zero vectors, which clothbake refuses: those rows become
    +z, and `usable` is False there."""
    n = max(dr.width(si_wi), dr.width(wo), n)
    view, light = _rows(si_wi, n), _rows(wo, n)
    below = view[:, 2] < 0
    view[below] *= _MIRROR
    light[below] *= _MIRROR
    usable = np.any(view != 0, axis=1) & np.any(light != 0, axis=1)
    view[~usable] = (0.0, 0.0, 1.0)
    light[~usable] = (0.0, 0.0, 1.0)
    return view, light, usable, below


# One evaluator (and its sampler, built on first use in a second or two) per fabric and
# spelling for the process: Mitsuba instantiates a plugin for every scene load, and
# `mitsuba.chi2` for every call of its functions.
_EVALUATORS = {}


def _evaluator(fabric, spelling, fabric_file):
    key = (fabric.name, fabric_file, spelling)
    if key not in _EVALUATORS:
        _EVALUATORS[key] = Evaluator(fabric, spelling)
    return _EVALUATORS[key]


class ClothbakeBSDF(mi.BSDF):
    """A clothbake fabric as a Mitsuba 3 BSDF (see the module documentation)."""

    def __init__(self, props):
        super().__init__(props)
        fabric = _fabric(props)
        table = _string(props, "table")
        spelling = f"table:{table}" if table else _string(props, "evaluator", "direct")
        self.evaluator = _evaluator(fabric, spelling, _string(props, "fabrics"))
        self.m_flags = _FLAGS
        self.m_components = [_FLAGS]

    def eval(self, ctx, si, wo, active=True):
        view, light, usable, _ = _pair(si.wi, wo)
        f = self.evaluator.eval(light, view)
        f[~usable] = 0.0
        return mi.Color3f(f.T.astype(np.float32))

    def pdf(self, ctx, si, wo, active=True):
        view, light, usable, _ = _pair(si.wi, wo)
        pdf = self.evaluator.pdf(view, light)
        pdf[~usable] = 0.0
        return mi.Float(pdf.astype(np.float32))

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        n = max(dr.width(sample1), dr.width(sample2))
        view, _, usable, below = _pair(si.wi, si.wi, n)
        n = len(view)
        xy = np.asarray(sample2.numpy(), dtype=np.float64).reshape(2, -1)
        z = np.asarray(sample1.numpy(), dtype=np.float64)
        u = np.stack([np.broadcast_to(c, (n,)) for c in (xy[0], xy[1], z)], axis=1)
        # Dr.Jit's samples are in [0, 1); float32 rounding can reach 1 exactly.
        u = np.minimum(u, np.nextafter(1.0, 0.0))
        light, pdf = self.evaluator.sample(view, u)
        drawn = usable & (pdf > 0)
        # A rejected draw has wi = 0: read +z in its place, then masked.
        light_read = np.where(drawn[:, None], light, (0.0, 0.0, 1.0))
        f = self.evaluator.eval(light_read, view)
        weight = np.where(drawn[:, None], f / np.where(drawn, pdf, 1.0)[:, None], 0.0)
        light[below] *= _MIRROR
        bs = dr.zeros(mi.BSDFSample3f, n)
        bs.wo = mi.Vector3f(light.T.astype(np.float32))
        bs.pdf = mi.Float(np.where(drawn, pdf, 0.0).astype(np.float32))
        bs.eta = 1.0
        bs.sampled_type = mi.UInt32(int(mi.BSDFFlags.GlossyReflection))
        bs.sampled_component = 0
        return bs, mi.Color3f(weight.T.astype(np.float32))

    def to_string(self):
        return f"ClothbakeBSDF[{self.evaluator.label}]"


mi.register_bsdf("clothbake", lambda props: ClothbakeBSDF(props))
