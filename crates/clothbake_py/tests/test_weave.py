"""Weaves from Python against `clothbake weave` of the same build: drawdowns, woven fabrics
evaluated pair by pair, their fabric files, and refusals naming the knob or draft."""

import json

import numpy as np
import pytest

import clothbake
from conftest import ROOT, unit_rows

WIF = ROOT / "tests" / "data" / "wif" / "twill_fiberworks_crlf.wif"


@pytest.mark.parametrize(
    "draft, expected",
    [
        ("plain", "#.\n.#\n"),
        ("basket:2", "##..\n##..\n..##\n..##\n"),
        ("twill:2/1", "##.\n.##\n#.#\n"),
        ("twill:2/1:s", "##.\n#.#\n.##\n"),
        ("satin:5", ".####\n##.##\n####.\n#.###\n###.#\n"),
    ],
)
def test_named_drawdowns(cli, draft, expected):
    assert clothbake.drawdown(draft) == expected
    assert cli(["weave", draft, "--drawdown"]) == expected


@pytest.mark.parametrize("draft", ["twill:3/1", "sateen:5/2", str(WIF)])
@pytest.mark.parametrize("back, swap", [(True, False), (False, True), (True, True)])
def test_back_and_swap_drawdowns_are_the_cli_s(cli, draft, back, swap):
    flags = ["--back"] * back + ["--swap"] * swap
    assert clothbake.drawdown(draft, back=back, swap=swap) == cli(
        ["weave", draft, "--drawdown", *flags]
    )


def cli_fabric(cli, tmp_path, draft, knobs, flags=()):
    """`clothbake weave DRAFT --yarn .. --warp .. --weft .. --out` and the file it wrote."""
    out = tmp_path / "woven.toml"
    args = ["weave", draft, "--out", str(out), *flags]
    for option, text in zip(["--yarn", "--warp", "--weft"], knobs):
        args += [option, text]
    cli(args)
    return out


def cli_eval(cli, fabrics, name, wi, wo):
    records = [{"wi": a.tolist(), "wo": b.tolist()} for a, b in zip(wi, wo)]
    out = cli(["eval", "--fabrics", str(fabrics), "--fabric", name], records)
    return np.array([json.loads(line)["f"] for line in out.splitlines()])


def body(text):
    """A fabric file without its comments (the header says which command made it)."""
    return "".join(line + "\n" for line in text.splitlines() if not line.startswith("#"))


@pytest.mark.parametrize(
    "draft, dicts, texts, flags",
    [
        (
            "satin:5",
            [{"fibre": "silk", "crimp": 20}, {"legs": 0.3, "colour": (0.9, 0.2, 0.1)}, None],
            ["fibre=silk,crimp=20", "legs=0.3,colour=0.9/0.2/0.1", ""],
            [],
        ),
        (
            "twill:3/1:s",
            [None, "cover=0.8,kd=0.1", {"colour": "#3050a0", "gamma_s": 8, "eta": 1.46}],
            ["", "cover=0.8,kd=0.1", "colour=#3050a0,gamma_s=8,eta=1.46"],
            ["--back", "--swap"],
        ),
        (str(WIF), [{"flatten": 0.9}, None, None], ["flatten=0.9", "", ""], []),
    ],
)
def test_a_woven_fabric_is_the_cli_s_pair_by_pair(cli, rng, tmp_path, draft, dicts, texts, flags):
    yarn, warp, weft = dicts
    fabric = clothbake.weave(
        draft, yarn, warp=warp, weft=weft, back="--back" in flags, swap="--swap" in flags
    )
    written = cli_fabric(cli, tmp_path, draft, texts, flags)
    # The same fabric, field for field: the file's body is ours.
    assert body(fabric.to_toml("made in Python")) == body(written.read_text())
    (theirs,) = clothbake.load_fabrics(written)
    assert fabric.name == theirs.name

    wi, wo = unit_rows(rng, 120), unit_rows(rng, 120)
    ours = clothbake.Evaluator(fabric, "direct").eval(wi, wo)
    np.testing.assert_array_equal(ours, cli_eval(cli, written, fabric.name, wi, wo))
    assert np.all(np.isfinite(ours)) and ours.max() > 0
    assert np.all(ours[(wi[:, 2] <= 0) | (wo[:, 2] <= 0)] == 0)

    # Saved with to_toml, the fabric reads back (in Python and on the commands) the same.
    saved = tmp_path / "saved.toml"
    saved.write_text(fabric.to_toml("woven in Python\nsecond line"))
    assert saved.read_text().startswith("# woven in Python\n# second line\n")
    (again,) = clothbake.load_fabrics(saved)
    np.testing.assert_array_equal(clothbake.Evaluator(again, "direct").eval(wi, wo), ours)
    np.testing.assert_array_equal(cli_eval(cli, saved, fabric.name, wi, wo), ours)


def test_knobs_as_a_dict_or_as_text_and_the_name():
    as_text = clothbake.weave("twill:2/2", "crimp=30,fibre=wool", weft="colour=0.2/0.3/0.4")
    as_dict = clothbake.weave(
        "twill:2/2", {"crimp": 30.0, "fibre": "wool"}, weft={"colour": [0.2, 0.3, 0.4]}
    )
    assert as_text.to_toml() == as_dict.to_toml()
    assert as_text.to_toml() != clothbake.weave("twill:2/2").to_toml()
    # The family's own knobs come after the shared ones.
    assert (
        clothbake.weave("plain", {"kd": 0.1}, warp={"kd": 0.2}).to_toml()
        == clothbake.weave("plain", warp={"kd": 0.2}, weft={"kd": 0.1}).to_toml()
    )
    assert clothbake.weave("plain", name="my_cloth").name == "my_cloth"
    assert "my_cloth" in clothbake.weave("plain", name="my_cloth").to_toml()


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: clothbake.weave("plain", {"crimp": 95}), "yarn: yarn knob 'crimp' must be within"),
        (lambda: clothbake.weave("plain", warp="legs=2"), "warp: yarn knob 'legs' must be within"),
        (lambda: clothbake.weave("plain", weft={"shine": 1}), "weft: unknown yarn knob 'shine'"),
        (lambda: clothbake.weave("plain", {"kd": "lots"}), "yarn knob 'kd' takes a number"),
        (lambda: clothbake.weave("plain", {"kd": float("nan")}), "yarn knob 'kd' must be within"),
        (lambda: clothbake.weave("plain", {"eta": True}), "yarn knob 'eta' takes a number"),
        (lambda: clothbake.weave("plain", {"colour": (1, 2, 3)}), "a colour is"),
        (lambda: clothbake.weave("plain", {"fibre": "mohair"}), "mohair"),
        (lambda: clothbake.weave("plain", "crimp"), "yarn: yarn knobs are key=value"),
        (lambda: clothbake.weave("plain", {1: 2}), "yarn: yarn knobs are named by strings"),
        (lambda: clothbake.weave("plain", 3), "yarn: expected a dict"),
        (lambda: clothbake.weave("twill:0/1"), "draft: weave 'twill:0/1'"),
        (lambda: clothbake.drawdown("tartan"), "draft: weave 'tartan'"),
        (lambda: clothbake.drawdown("missing.wif"), "missing.wif"),
        (lambda: clothbake.weave("plain", name=""), "name"),
    ],
)
def test_bad_knobs_and_drafts_raise_an_error_that_names_them(call, message):
    with pytest.raises(clothbake.ClothbakeError, match=message.replace("(", r"\(")):
        call()
