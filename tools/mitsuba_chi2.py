# Mitsuba's BSDFAdapter chi-square test of the clothbake sampler for the built-in fabrics at
# test_mitsuba.py's views; prints p-value, histogram and pdf sums per case
# (docs/notebook/2026-12-07-sampler-support.md). Usage: .venv/bin/python tools/mitsuba_chi2.py [FABRIC...]
import math, os, re, sys, tempfile, pathlib
os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1")
import drjit as dr, mitsuba as mi
mi.set_variant("llvm_ad_rgb")
import clothbake, clothbake.mitsuba
from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain
VIEWS = [(2, 0), (7, 200), (10, 90), (30, 30), (50, 135), (70, 60), (88, 200)]
fabrics = sys.argv[1:] or clothbake.fabric_names()
d = pathlib.Path(tempfile.mkdtemp())
n_cases = len(clothbake.fabric_names()) * len(VIEWS)
for name in fabrics:
    clothbake.bake(clothbake.Fabric.builtin(name), d / f"{name}.exr", layout="thread_frame", resolution=12)
    for el, az in VIEWS:
        e, a = math.radians(el), math.radians(az)
        wi = [math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)]
        extra = f'<string name="fabric" value="{name}"/><string name="table" value="{d / (name + ".exr")}"/>'
        sf, pf = BSDFAdapter("clothbake", extra, wi=wi)
        chi2 = ChiSquareTest(domain=SphericalDomain(), sample_func=sf, pdf_func=pf, sample_dim=3, sample_count=300_000, ires=12)
        ok = chi2.run(significance_level=0.01, test_count=n_cases)
        m = chi2.messages
        hs = re.search(r"Histogram sum = ([0-9.]+).*PDF sum = ([0-9.]+)", m)
        p = re.search(r"p-value = ([0-9.e-]+)", m)
        print(f"{name:28} {el:3}°/{az:3}°  {'pass' if ok else 'FAIL'}  p {p.group(1) if p else '?':>10}  histogram sum {hs.group(1)}  pdf sum {hs.group(2)}", flush=True)
