"""The ``clothbake`` BSDF inside Mitsuba 3: registered by name, and its sampler through
Mitsuba's own chi-square test (``mitsuba.chi2``), for every fabric."""

import math
import os
import pathlib

import numpy as np
import pytest

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1")
import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant("llvm_ad_rgb")

import clothbake  # noqa: E402
import clothbake.mitsuba  # noqa: E402,F401  (registers the plugin)
from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain  # noqa: E402

# Outgoing (view) directions, elevation and azimuth from thread 1 in degrees: down to 2°,
# across the threads' azimuths.
VIEWS = [(2, 0), (10, 90), (30, 30), (50, 135), (70, 60), (88, 200)]
CASES = [(f, v) for f in clothbake.fabric_names() for v in VIEWS]


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    """Small tables for F in the sample weights (the chi-square test reads only the pdf and
    where the draws land, which are the sampler's whatever F is; a lookup keeps a million
    weights cheap)."""
    directory = tmp_path_factory.mktemp("mitsuba_tables")
    for name in clothbake.fabric_names():
        clothbake.bake(
            clothbake.Fabric.builtin(name),
            directory / f"{name}.exr",
            layout="thread_frame",
            resolution=12,
        )
    return directory


def test_the_plugin_loads_by_name_from_a_dict_and_from_xml(tables):
    table = str(tables / "velvet.exr")
    from_dict = mi.load_dict({"type": "clothbake", "fabric": "velvet", "table": table})
    from_xml = mi.load_string(
        f'<bsdf version="3.0.0" type="clothbake"><string name="fabric" value="velvet"/>'
        f'<string name="table" value="{table}"/></bsdf>'
    )
    for bsdf in (from_dict, from_xml):
        assert "table thread_frame R=12" in str(bsdf)
    with pytest.raises(Exception, match="fabric"):
        mi.load_dict({"type": "clothbake"})


def test_eval_is_clothbake_s_f_with_light_and_view_swapped_and_two_sided(tables):
    """Mitsuba's eval(si.wi = view, wo = light) is F(wi = light, wo = view); seen from below
    the pair is mirrored (x, y, z) -> (x, -y, -z)."""
    table = str(tables / "polyester_satin_charmeuse.exr")
    bsdf = mi.load_dict(
        {"type": "clothbake", "fabric": "polyester_satin_charmeuse", "table": table}
    )
    evaluator = clothbake.Evaluator(
        clothbake.Fabric.builtin("polyester_satin_charmeuse"), f"table:{table}"
    )
    view = np.array([0.5, 0.3, math.sqrt(1 - 0.34)])
    light = np.array([-0.4, -0.2, math.sqrt(1 - 0.2)])
    expected = evaluator.eval(light[None], view[None])[0]
    for sign in (1.0, -1.0):
        flip = np.array([1.0, sign, sign])
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*map(float, view * flip))
        value = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(*map(float, light * flip)))
        np.testing.assert_allclose(np.array(value).ravel(), expected, rtol=1e-6)


def drawn_directions(bsdf, wi):
    """Mitsuba's BSDFAdapter sample function, except that every draw with pdf > 0 counts.
    The adapter drops draws whose weight is 0 as failed, which is right for a BSDF whose f
    is positive wherever it samples; the model's F is exactly 0 on part of velvet's
    hemisphere (no tangent sample faces both directions) where the sampler's cosine-weighted
    share still draws 0.6–0.8% of its directions. Those are draws of the density all the
    same, and the test is of the density."""

    def sample(sample):
        si = dr.zeros(mi.SurfaceInteraction3f, dr.width(sample))
        si.wi = wi
        bs, _ = bsdf.sample(mi.BSDFContext(), si, sample[0], mi.Vector2f(sample[1], sample[2]))
        return bs.wo, dr.select(bs.pdf > 0, 1.0, 0.0)

    return sample


@pytest.mark.parametrize("fabric, view", CASES, ids=[f"{f}-{e}deg-{a}" for f, (e, a) in CASES])
def test_the_sampler_passes_mitsuba_s_chi_square_test(tables, fabric, view):
    elevation, azimuth = (math.radians(x) for x in view)
    wi = [
        math.cos(elevation) * math.cos(azimuth),
        math.cos(elevation) * math.sin(azimuth),
        math.sin(elevation),
    ]
    extra = f'<string name="fabric" value="{fabric}"/><string name="table" value="{tables / (fabric + ".exr")}"/>'
    _, pdf_func = BSDFAdapter("clothbake", extra, wi=wi)
    bsdf = mi.load_string(f'<bsdf version="3.0.0" type="clothbake">{extra}</bsdf>')
    chi2 = ChiSquareTest(
        domain=SphericalDomain(),
        sample_func=drawn_directions(bsdf, wi),
        pdf_func=pdf_func,
        sample_dim=3,
        sample_count=300_000,
        # The sampler's pdf is constant on cells of 2.8° × 5.6°, about as wide as satin's
        # lobe, and the harness integrates it over each of its cells by the trapezoid rule
        # on ires² points: at the default 4 that rule is 1% off on the cells a step crosses
        # (both satins at 2° and 10° are rejected), at 12 it is 0.02% off.
        ires=12,
    )
    # Šidák-corrected over every case of this test, as Mitsuba's own BSDF tests correct.
    assert chi2.run(significance_level=0.01, test_count=len(CASES)), chi2.messages


def test_the_example_scene_file_renders(tables):
    """examples/sphere.xml (docs/python.md) with a small table, at 4 draws per pixel."""
    dr.set_flag(dr.JitFlag.SymbolicLoops, False)
    dr.set_flag(dr.JitFlag.SymbolicCalls, False)
    scene = mi.load_file(
        str(pathlib.Path(__file__).parents[1] / "examples" / "sphere.xml"),
        table=str(tables / "velvet.exr"),
        spp=4,
    )
    image = np.array(mi.render(scene))
    assert image.shape == (128, 128, 3)
    assert np.isfinite(image).all() and image.max() > 0
