"""The bindings against the Rust library (through the `clothbake` binary of the same build),
pair by pair, and their refusals."""

import json
import threading
import time

import numpy as np
import pytest

import clothbake
from conftest import ROOT, unit_rows

# Every evaluator of the registry but the table's, whose file the tests bake first.
MODEL_EVALUATORS = ["direct", "paper:16", "resonant", "constant"]


@pytest.fixture(scope="module")
def small_tables(tmp_path_factory):
    """Each built-in fabric baked by the bindings at a small resolution (seconds, not the
    default's half minute)."""
    directory = tmp_path_factory.mktemp("tables")
    return {
        name: clothbake.bake(
            clothbake.Fabric.builtin(name), directory / f"{name}.exr", resolution=12
        )
        for name in clothbake.fabric_names()
    }


def cli_eval(cli, fabric, spelling, wi, wo):
    records = [{"wi": a.tolist(), "wo": b.tolist()} for a, b in zip(wi, wo)]
    out = cli(["eval", "--fabric", fabric, "--evaluator", spelling], records)
    return np.array([json.loads(line)["f"] for line in out.splitlines()])


def test_fabric_names_are_the_cli_s(cli):
    listed = cli(["fabrics"])
    for name in clothbake.fabric_names():
        assert name in listed
    assert len(clothbake.fabric_names()) == 6


@pytest.mark.parametrize("fabric", clothbake.fabric_names())
def test_every_evaluator_agrees_with_the_rust_library_pair_by_pair(cli, rng, fabric, small_tables):
    # The whole sphere: half the pairs have a direction below the horizon, where F is 0.
    wi, wo = unit_rows(rng, 150), unit_rows(rng, 150)
    table = small_tables[fabric]
    for spelling in MODEL_EVALUATORS + [f"table:{table.evaluator().spelling[len('table:'):]}"]:
        ours = clothbake.Evaluator(clothbake.Fabric.builtin(fabric), spelling).eval(wi, wo)
        theirs = cli_eval(cli, fabric, spelling, wi, wo)
        # f64 evaluators exactly (the JSON round-trips f64); the table's f32 lookup too,
        # since its batch and its single lookup are the same arithmetic
        # (tests/tables/table.rs: f32_lookup_follows_the_f64_lookup).
        np.testing.assert_array_equal(ours, theirs, err_msg=f"{fabric} {spelling}")
        assert np.all(ours[(wi[:, 2] <= 0) | (wo[:, 2] <= 0)] == 0)


@pytest.mark.parametrize("fabric", ["polyester_satin_charmeuse", "velvet"])
def test_sampler_draws_and_densities_are_the_rust_library_s(cli, rng, fabric):
    evaluator = clothbake.Evaluator(clothbake.Fabric.builtin(fabric), "direct")
    wo = unit_rows(rng, 200, upper=True)
    u = rng.random((200, 3))
    wi, pdf = evaluator.sample(wo, u)
    out = cli(
        ["sample", "--fabric", fabric], [{"wo": a.tolist(), "u": b.tolist()} for a, b in zip(wo, u)]
    )
    records = [json.loads(line) for line in out.splitlines()]
    for k, record in enumerate(records):
        if record["wi"] is None:
            assert pdf[k] == 0 and np.all(wi[k] == 0)
        else:
            np.testing.assert_array_equal(wi[k], record["wi"])
            assert pdf[k] == record["pdf"]
    drawn = pdf > 0
    assert drawn.mean() > 0.9
    # The density at the drawn directions, as read back: reading normalises wi again, which
    # moves it by an ulp or so, hence not bit for bit.
    np.testing.assert_allclose(evaluator.pdf(wo[drawn], wi[drawn]), pdf[drawn], rtol=1e-12)


def test_a_baked_table_checks_as_clothbake_check_reports_it(cli, small_tables, tmp_path):
    table = small_tables["linen_plain"]
    assert (table.layout, table.resolution, table.fabric.name) == (
        "split_frame",
        12,
        "linen_plain",
    )
    error = table.check(pairs=2000)
    printed = cli(["check", str(table.evaluator().spelling[len("table:") :]), "--pairs", "2000"])
    line = next(l for l in printed.splitlines() if l.strip().startswith("uniform pairs"))
    assert f"{100 * error['uniform']['relative_rms']:.3f}%" in line
    # Deterministic: the same fabric baked again gives the same bytes.
    again = clothbake.bake(
        clothbake.Fabric.builtin("linen_plain"), tmp_path / "again.exr", resolution=12
    )
    first = table.evaluator().spelling[len("table:") :]
    assert (tmp_path / "again.exr").read_bytes() == open(first, "rb").read()
    assert again.hash == table.hash


def test_fabric_files_load_and_bad_ones_name_the_field(tmp_path):
    good = tmp_path / "good.toml"
    good.write_text((ROOT / "tables" / "fabrics.toml").read_text())
    assert [f.name for f in clothbake.load_fabrics(good)] == clothbake.fabric_names()
    bad = tmp_path / "bad.toml"
    bad.write_text(good.read_text().replace("eta = 1.46", "eta = -1.46", 1))
    with pytest.raises(clothbake.ClothbakeError, match="eta"):
        clothbake.load_fabrics(bad)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: clothbake.Fabric.builtin("tweed"), "tweed"),
        (
            lambda: clothbake.Evaluator(clothbake.Fabric.builtin("velvet"), "nearest"),
            "unknown evaluator",
        ),
        (lambda: clothbake.Evaluator(clothbake.Fabric.builtin("velvet"), "paper:0"), "paper:0"),
        (
            lambda: clothbake.Evaluator(
                clothbake.Fabric.builtin("velvet"), "table:/nonexistent/velvet.exr"
            ),
            "nonexistent",
        ),
        (
            lambda: DIRECT().eval(np.zeros((4, 2)), np.zeros((4, 2))),
            r"wi: expected an array of shape \(N, 3\)",
        ),
        (lambda: DIRECT().eval([[0, 0, 1]], [[0, 0, 1], [0, 0, 1]]), "must match"),
        (
            lambda: DIRECT().eval([[0, 0, 1], [0, 0, 0]], [[0, 0, 1]] * 2),
            "row 1: wi is the zero vector",
        ),
        (
            lambda: DIRECT().eval([[0, 0, 1]], [[np.nan, 0, 1]]),
            "row 0: wo has a non-finite component",
        ),
        (lambda: DIRECT().sample([[0, 0, 1]], [[0.5, 1.0, 0.2]]), r"row 0: u = \[0.5, 1.0, 0.2\]"),
        (
            lambda: clothbake.bake(
                clothbake.Fabric.builtin("velvet"), "/tmp/x.exr", layout="octree"
            ),
            "layout",
        ),
        (
            lambda: clothbake.bake(clothbake.Fabric.builtin("velvet"), "/tmp/x.exr", resolution=1),
            "resolution",
        ),
        (lambda: clothbake.Table.load(ROOT / "README.md"), "README"),
        (lambda: DIRECT().eval("not an array", [[0, 0, 1]]), "could not convert"),
    ],
)
def test_bad_input_raises_an_exception_that_names_it(call, message):
    with pytest.raises((clothbake.ClothbakeError, TypeError, ValueError), match=message):
        call()


def DIRECT():
    return clothbake.Evaluator(clothbake.Fabric.builtin("velvet"), "direct")


def test_the_gil_is_released_during_a_batch(rng):
    """While one thread evaluates a long batch, another runs Python: with the GIL held
    through the batch, no tick could land inside it."""
    evaluator = DIRECT()
    wi, wo = unit_rows(rng, 3000, upper=True), unit_rows(rng, 3000, upper=True)
    span = {}

    def work():
        span["start"] = time.perf_counter()
        evaluator.eval(wi, wo)
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    inside = [t for t in ticks if span["start"] < t < span["end"]]
    assert span["end"] - span["start"] > 0.05, "batch too short to tell"
    assert len(inside) >= 10, f"{len(inside)} ticks in a {span['end'] - span['start']:.2f} s batch"


def test_any_array_layout_and_float_type_reads_the_same(rng):
    """C-contiguous float64 rows are read in place; strided, Fortran-ordered and float32
    arrays and nested lists are read through a copy, to the same values."""
    evaluator = DIRECT()
    wi, wo = unit_rows(rng, 40, upper=True), unit_rows(rng, 40, upper=True)
    expected = evaluator.eval(wi, wo)
    doubled = np.repeat(wi, 2, axis=0)[::2]
    assert not doubled.flags.c_contiguous
    np.testing.assert_array_equal(evaluator.eval(doubled, wo), expected)
    np.testing.assert_array_equal(evaluator.eval(np.asfortranarray(wi), wo.tolist()), expected)
    single = evaluator.eval(wi.astype(np.float32), wo)
    np.testing.assert_allclose(single, evaluator.eval(wi.astype(np.float32).astype(np.float64), wo))
