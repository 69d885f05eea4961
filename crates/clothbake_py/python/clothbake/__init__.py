"""clothbake from Python: the Sadeghi et al. 2013 microcylinder cloth model.

Fabrics, every evaluator of F(wi, wo) that clothbake registers (``direct``, ``paper[:N]``,
``resonant[:S/V/B]``, ``table[:PATH]``, ``constant``), the importance sampler, and baked
tables, fabrics woven from a draft (``weave``) or fitted to
measured F (``fit``), over NumPy arrays of directions in the cloth frame (x along thread 1, y along
thread 2, z the normal; ``wi`` towards the light, ``wo`` towards the viewer). F is the
cosine-weighted patch transfer: a distant light of perpendicular irradiance E gives outgoing
radiance E * F(wi, wo).

>>> import clothbake, numpy as np
>>> velvet = clothbake.Fabric.builtin("velvet")
>>> direct = clothbake.Evaluator(velvet, "direct")
>>> wi = np.array([[0.0, 0.0, 1.0]]); wo = np.array([[0.6, 0.0, 0.8]])
>>> direct.eval(wi, wo).shape
(1, 3)

``clothbake.mitsuba`` registers the ``clothbake`` BSDF with Mitsuba 3 (docs/python.md).
"""

from ._clothbake import (
    ClothbakeError,
    Evaluator,
    Fabric,
    Table,
    __version__,
    bake,
    drawdown,
    environment_map,
    evaluator_syntaxes,
    fabric_names,
    fit,
    load_fabrics,
    load_scene,
    weave,
)

__all__ = [
    "ClothbakeError",
    "Evaluator",
    "Fabric",
    "Table",
    "__version__",
    "bake",
    "drawdown",
    "environment_map",
    "evaluator_syntaxes",
    "fabric_names",
    "fit",
    "load_fabrics",
    "load_scene",
    "weave",
]
