"""docs/python.md's Python examples run as written, in order, in a scratch directory."""

import os
import re
import subprocess
import sys

from conftest import ROOT


def test_the_docs_examples_run_as_written(tmp_path):
    page = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, flags=re.S)
    assert len(blocks) == 3, "the page's examples: the API, Mitsuba, weaves and fits"
    for k, code in enumerate(blocks):
        script = tmp_path / f"example{k}.py"
        script.write_text(code)
        env = dict(os.environ)
        env.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1")
        done = subprocess.run(
            [sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True
        )
        assert done.returncode == 0, f"example {k}:\n{done.stdout}\n{done.stderr}"
    assert (tmp_path / "velvet-small.exr").is_file()
    assert (tmp_path / "velvet-mitsuba.exr").stat().st_size > 0
    assert (tmp_path / "my-fabrics.toml").is_file() and (tmp_path / "my_satin.exr").is_file()
