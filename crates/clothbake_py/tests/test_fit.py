"""Fits from NumPy arrays: a built-in fabric recovered from its own samples, the same fit as
`clothbake fit` of the same samples written as a file, and refusals naming the row."""

import json
import re

import numpy as np
import pytest

import clothbake

FABRIC = "linen_plain"


def upper_rows(rng, n):
    """n directions strictly above the horizon (at least about 3° of elevation)."""
    w = rng.normal(size=(n, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    w[:, 2] = np.abs(w[:, 2]) + 0.05
    return w / np.linalg.norm(w, axis=1, keepdims=True)


@pytest.fixture
def samples(rng):
    """300 noiseless samples of the built-in fabric's F by the direct evaluator."""
    wi, wo = upper_rows(rng, 300), upper_rows(rng, 300)
    f = clothbake.Evaluator(clothbake.Fabric.builtin(FABRIC), "direct").eval(wi, wo)
    return wi, wo, f


def moved(fabric, tmp_path):
    """The fabric with a few of its parameters moved slightly, through its fabric file."""
    text = fabric.to_toml()
    text = re.sub(r"gamma_s_deg = ([0-9.]+)", lambda m: f"gamma_s_deg = {float(m[1]) * 1.15}", text)
    text = re.sub(r"\nkd = ([0-9.]+)", lambda m: f"\nkd = {float(m[1]) * 0.85}", text)
    assert text != fabric.to_toml()
    path = tmp_path / "moved.toml"
    path.write_text(text)
    (start,) = clothbake.load_fabrics(path)
    return start


def body(text):
    return "".join(line + "\n" for line in text.splitlines() if not line.startswith("#"))


def test_a_fabric_is_recovered_from_its_own_samples(samples, tmp_path, rng):
    wi, wo, f = samples
    truth = clothbake.Fabric.builtin(FABRIC)
    start = moved(truth, tmp_path)
    before = clothbake.Evaluator(start).eval(wi, wo)
    assert np.linalg.norm(before - f) / np.linalg.norm(f) > 0.01

    fabric, report = clothbake.fit(wi, wo, f, like=start, name="recovered")
    assert fabric.name == "recovered"
    assert report["holdout_count"] == 60 and report["fit_count"] == 240
    assert report["fit_relative_rms"] < 1e-3
    assert report["holdout_relative_rms"] < 1e-3
    assert len(report["parameters"]) == len(report["values"]) > 0
    assert set(report["values"]) == set(report["parameters"])
    assert all(isinstance(d, str) for d in report["flat_directions"])
    assert report["evaluations"] > 0

    # On new directions too.
    wi2, wo2 = upper_rows(rng, 200), upper_rows(rng, 200)
    truth_f = clothbake.Evaluator(truth).eval(wi2, wo2)
    ours = clothbake.Evaluator(fabric).eval(wi2, wo2)
    assert np.linalg.norm(ours - truth_f) / np.linalg.norm(truth_f) < 2e-3

    # The fitted fabric saves and reads back.
    saved = tmp_path / "recovered.toml"
    saved.write_text(fabric.to_toml("fitted in Python"))
    (again,) = clothbake.load_fabrics(saved)
    np.testing.assert_array_equal(clothbake.Evaluator(again).eval(wi2, wo2), ours)


def test_the_fit_is_clothbake_fit_s_of_the_same_samples(cli, samples, tmp_path):
    wi, wo, f = samples
    start = moved(clothbake.Fabric.builtin(FABRIC), tmp_path)
    file = tmp_path / "samples.jsonl"
    file.write_text(
        "".join(
            json.dumps({"wi": a.tolist(), "wo": b.tolist(), "f": c.tolist()}) + "\n"
            for a, b, c in zip(wi, wo, f)
        )
    )
    out = tmp_path / "fitted.toml"
    cli(["fit", str(file), "--like", start.name, "--fabrics", str(tmp_path / "moved.toml"),
         "--starts", "2", "--out", str(out)])
    fabric, report = clothbake.fit(wi, wo, f, like=start, starts=2)
    assert body(fabric.to_toml()) == body(out.read_text())
    assert f"{100 * report['holdout_relative_rms']:.4f}%" in out.read_text()


def test_weights_and_the_hold_out(samples):
    wi, wo, f = samples
    start = clothbake.Fabric.builtin(FABRIC)
    _, report = clothbake.fit(wi, wo, f, like=start, weight=np.full(300, 2.0), hold_out=0)
    assert report["holdout_count"] == 0 and report["holdout_relative_rms"] is None
    _, fixed = clothbake.fit(wi[:100], wo[:100], f[:100], like=start, fibre="silk")
    assert not any("eta" in name for name in fixed["parameters"])


def bad(samples, which, row, value):
    wi, wo, f = (a.copy() for a in samples)
    {"wi": wi, "wo": wo, "f": f}[which][row] = value
    return lambda: clothbake.fit(wi, wo, f, like=clothbake.Fabric.builtin(FABRIC))


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda s: bad(s, "wi", 7, [np.nan, 0.0, 1.0]), r"row 7\b.*wi"),
        (lambda s: bad(s, "wo", 12, [0.3, 0.2, -0.5]), r"row 12\b.*wo.*horizon"),
        (lambda s: bad(s, "wi", 3, [0.0, 0.0, 0.0]), r"row 3\b.*wi"),
        (lambda s: bad(s, "f", 5, [0.1, -0.2, 0.1]), r"row 5\b.*f"),
        (lambda s: bad(s, "f", 9, [0.1, np.inf, 0.1]), r"row 9\b.*f"),
        (
            lambda s: lambda: clothbake.fit(
                s[0][:6], s[1][:6], s[2][:6], like=clothbake.Fabric.builtin(FABRIC)
            ),
            r"fewer than",
        ),
        (
            lambda s: lambda: clothbake.fit(
                s[0], s[1], s[2], like=clothbake.Fabric.builtin(FABRIC), weight=-np.ones(300)
            ),
            r"row 0\b.*weight",
        ),
        (
            lambda s: lambda: clothbake.fit(s[0], s[1][:10], s[2], like=clothbake.Fabric.builtin(FABRIC)),
            "wi has 300 rows and wo has 10",
        ),
        (
            lambda s: lambda: clothbake.fit(s[0], s[1], s[2][:, :2], like=clothbake.Fabric.builtin(FABRIC)),
            r"f: expected an array of shape \(N, 3\)",
        ),
        (lambda s: lambda: clothbake.fit(*s), "exactly one of like= .* and weave="),
        (
            lambda s: lambda: clothbake.fit(*s, like=clothbake.Fabric.builtin(FABRIC), fibre="mohair"),
            "fibre: unknown fibre 'mohair'",
        ),
        (
            lambda s: lambda: clothbake.fit(*s, like=clothbake.Fabric.builtin(FABRIC), starts=0),
            "starts: 0",
        ),
        (
            lambda s: lambda: clothbake.fit(*s, like=clothbake.Fabric.builtin(FABRIC), name=""),
            "field 'name'",
        ),
    ],
)
def test_bad_arrays_raise_an_error_that_names_the_row(samples, make, message):
    with pytest.raises(clothbake.ClothbakeError, match=message):
        make(samples)()


def test_a_weave_s_yarn_knobs_are_fitted(rng):
    truth = clothbake.weave("satin:5", {"crimp": 20, "kd": 0.2}, name="woven")
    wi, wo = upper_rows(rng, 300), upper_rows(rng, 300)
    f = clothbake.Evaluator(truth).eval(wi, wo)
    fabric, report = clothbake.fit(wi, wo, f, weave="satin:5", yarn={"crimp": 25}, fibre="silk")
    assert fabric.name == "satin_5_2"
    assert "warp.crimp" in report["parameters"] and "weft.kd" in report["parameters"]
    assert not any(name.endswith("eta") for name in report["parameters"])
    assert report["holdout_relative_rms"] < 0.05
    with pytest.raises(clothbake.ClothbakeError, match="yarn: unknown yarn knob 'shine'"):
        clothbake.fit(wi, wo, f, weave="satin:5", yarn={"shine": 1})
    with pytest.raises(clothbake.ClothbakeError, match="go with weave="):
        clothbake.fit(wi, wo, f, like=truth, yarn={"crimp": 20})
