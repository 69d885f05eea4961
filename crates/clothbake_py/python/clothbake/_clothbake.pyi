"""Type stubs of the extension module (crates/clothbake_py/src/lib.rs)."""

import os
from typing import Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
_Path = Union[str, os.PathLike[str]]
_Directions = npt.ArrayLike  # shape (N, 3), directions in the cloth frame (normalised as read)
# Yarn knobs: {"crimp": 30, "fibre": "silk", "colour": (0.8, 0.1, 0.1)} or "crimp=30,fibre=silk"
_Knobs = Optional[Union[str, Mapping[str, Union[str, float, Sequence[float]]]]]

class ClothbakeError(ValueError):
    """A fabric, evaluator, table, file or array that clothbake refuses; the message names
    what is wrong."""

class Fabric:
    """One fabric of the model: two thread families with their tangent curves."""

    @staticmethod
    def builtin(name: str) -> Fabric:
        """The built-in fabric ``name`` (one of ``fabric_names()``)."""

    @property
    def name(self) -> str: ...
    def to_toml(self, header: str = "") -> str:
        """The fabric as a fabric file (TOML, one ``[[fabric]]``), each line of ``header`` a
        ``#`` comment; it reads back with ``load_fabrics`` and the commands' ``--fabrics``."""

class Evaluator:
    """F(wi, wo) of one fabric by one evaluator of the registry, with the importance sampler
    that fits it. ``evaluator`` is spelled as on every clothbake command; ``table`` without a
    path reads ``TABLES/NAME.exr``."""

    def __init__(
        self, fabric: Fabric, evaluator: str = "direct", tables: _Path = "tables"
    ) -> None: ...
    @property
    def spelling(self) -> str:
        """The spelling that parses back to this evaluator (``paper:32``)."""

    @property
    def label(self) -> str:
        """A short description (``table split_frame R=31``)."""

    def eval(self, wi: _Directions, wo: _Directions) -> npt.NDArray[np.float64]:
        """F(wi, wo) per row, RGB, shape (N, 3); 0 where either direction is on or below
        the horizon. The GIL is released while the batch runs."""

    def sample(
        self, wo: _Directions, u: npt.ArrayLike
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Directions wi (N, 3) drawn for each wo from three uniform numbers in [0, 1) per
        row of u, and pdf(wi | wo) per unit solid angle (N,); a rejected draw has wi = 0 and
        pdf = 0."""

    def pdf(self, wo: _Directions, wi: _Directions) -> npt.NDArray[np.float64]:
        """pdf(wi | wo) per unit solid angle, shape (N,); 0 unless both are above the
        horizon."""

class Table:
    """A baked table read from its EXR file, with the provenance it records."""

    @staticmethod
    def load(path: _Path) -> Table: ...
    @property
    def layout(self) -> str: ...
    @property
    def resolution(self) -> int: ...
    @property
    def fabric(self) -> Fabric: ...
    @property
    def byte_size(self) -> int: ...
    @property
    def hash(self) -> str: ...
    def check(self, pairs: int = 20000) -> dict[str, dict[str, float]]:
        """The table's error against the direct evaluation of its fabric (as ``clothbake
        check``): per pair set, ``relative_rms``, ``max_abs`` and ``max_abs_at_value``."""

    def evaluator(self) -> Evaluator:
        """``Evaluator(self.fabric, "table:PATH")``."""

def fabric_names() -> list[str]:
    """The names of the built-in fabrics."""

def load_fabrics(path: _Path) -> list[Fabric]:
    """Every fabric of a fabric file (TOML), validated."""

def evaluator_syntaxes() -> list[str]:
    """The registered evaluators' spellings."""

def bake(
    fabric: Fabric, path: _Path, layout: Optional[str] = None, resolution: Optional[int] = None
) -> Table:
    """Bakes ``fabric`` into a table of ``layout`` (default ``split_frame``) at
    ``resolution`` (default: the layout's), written to ``path`` atomically."""

def load_scene(path: Optional[_Path] = None) -> dict:
    """The scene ``clothbake render`` draws (built-in, or the scene file at ``path``):
    ``fabrics``, ``exposure``, ``camera`` (``eye``, ``target``, ``fov_y_deg``; +y up),
    ``lights`` (dicts by ``kind``), and ``mesh`` arrays: ``positions``, ``normals``,
    ``tangents`` (N, 3), ``uvs`` (N, 2), ``faces`` (M, 3)."""

def environment_map(source: str = "studio") -> npt.NDArray[np.float32]:
    """The environment ``--env SOURCE`` names (``studio``, ``sky``, ``overcast``,
    ``interior``, ``uniform``, or an ``.hdr``/``.exr`` file) as an (H, W, 3) array of linear
    radiance; row 0 looks up (+y), u = 1/2 + atan2(d.x, -d.z)/2pi, v = acos(d.y)/pi."""

def weave(
    draft: str,
    yarn: _Knobs = None,
    warp: _Knobs = None,
    weft: _Knobs = None,
    back: bool = False,
    swap: bool = False,
    name: Optional[str] = None,
) -> Fabric:
    """The fabric woven from ``draft`` (``plain``, ``basket:N``, ``twill:N/M[:s|:z]``,
    ``satin:N[/STEP]``, ``sateen:N[/STEP]``, or a WIF file), as ``clothbake weave`` makes it:
    ``yarn`` knobs for both families, then ``warp``'s (thread 1) and ``weft``'s (thread 2);
    ``back`` weaves the back, ``swap`` exchanges warp and weft before the knobs apply."""

def drawdown(draft: str, back: bool = False, swap: bool = False) -> str:
    """The draft's drawdown, one line per pick (pick 1 first): ``#`` where the warp is on
    top, ``.`` where the weft is."""

def fit(
    wi: _Directions,
    wo: _Directions,
    f: npt.ArrayLike,
    like: Optional[Fabric] = None,
    weave: Optional[str] = None,
    yarn: _Knobs = None,
    warp: _Knobs = None,
    weft: _Knobs = None,
    back: bool = False,
    swap: bool = False,
    weight: Optional[npt.ArrayLike] = None,
    fibre: Optional[str] = None,
    name: Optional[str] = None,
    starts: Optional[int] = None,
    hold_out: int = 5,
) -> tuple[Fabric, dict]:
    """A fabric fitted to measured F (rows of ``f``, (N, 3) RGB with cosines, at ``wi``
    and ``wo`` (N, 3) in the patch frame, above the horizon; optional ``weight`` (N,)) as
    ``clothbake fit`` fits a sample file: from ``like`` (a fabric's parameters) or ``weave``
    (a draft's yarn knobs, starting from ``yarn``/``warp``/``weft``/``back``/``swap`` as in
    ``weave()``); ``fibre`` fixes eta; every ``hold_out``-th row is held out. Returns the
    fabric and a report: ``fit_relative_rms``, ``holdout_relative_rms``, ``fit_count``,
    ``holdout_count``, ``parameters``, ``values``, ``bounds``, ``flat_directions``,
    ``singular_values``, ``start_objectives``, ``best_start``, ``evaluations``,
    ``termination``. Each refused row is named (counted from 0)."""
