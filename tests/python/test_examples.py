"""The quick-start examples run, and README.md shows them verbatim."""

import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO_ROOT

QUICKSTART_PY = REPO_ROOT / "examples" / "fmpy_quickstart.py"
QUICKSTART_C = REPO_ROOT / "cpp-harness" / "examples" / "quickstart.c"
README = REPO_ROOT / "README.md"


def fenced_blocks(text: str, lang: str) -> list[str]:
    """Contents of every ```lang fenced block (the fence line excluded)."""
    pattern = re.compile(r"^```" + re.escape(lang) + r"[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)
    return [m.group(1) for m in pattern.finditer(text)]


def normalized(text: str) -> str:
    return text.strip("\n") + "\n"


def test_fmpy_quickstart_runs(fmu_path, tmp_path):
    assert fmu_path.is_file()
    proc = subprocess.run(
        [sys.executable, str(QUICKSTART_PY)], cwd=tmp_path, capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = proc.stdout
    assert "Warning" not in out + proc.stderr, out + proc.stderr
    truth = re.search(r"truth \(x, y, z\) = \(([-\d.]+), ([-\d.]+), ([-\d.]+)\)", out)
    est = re.search(r"estimate: x = ([-\d.]+), y = ([-\d.]+), z = ([-\d.]+)", out)
    sig = re.search(r"1-sigma: +x = ([-\d.]+), y = ([-\d.]+), z = ([-\d.]+)", out)
    assert truth and est and sig, out
    truth, est, sig = (np.array([float(v) for v in m.groups()]) for m in (truth, est, sig))
    assert np.all(np.abs(est - truth) < 1.0), out
    assert np.all(sig < 1.0) and np.all(sig > 0.0), out


def test_readme_python_blocks_are_the_examples():
    """Every ```python block of README.md is one of examples/*.py verbatim, and the
    quick-starts are all shown (the Python package's examples run in
    test_package_api.py and test_package_campaign.py)."""
    assert README.is_file(), "README.md is missing"
    blocks = fenced_blocks(README.read_text(), "python")
    examples = {p.name: normalized(p.read_text()) for p in sorted((REPO_ROOT / "examples").glob("*.py"))}
    shown = set()
    for i, block in enumerate(blocks):
        match = [name for name, text in examples.items() if text == normalized(block)]
        assert match, f"README.md ```python block {i + 1} is none of examples/*.py verbatim"
        shown.update(match)
    for name in ("fmpy_quickstart.py", "relnav_python_quickstart.py", "relnav_campaign.py"):
        assert name in shown, f"README.md should show examples/{name} verbatim in a ```python block"


def test_readme_c_blocks_are_the_c_quickstart():
    assert README.is_file(), "README.md is missing"
    assert QUICKSTART_C.is_file(), f"{QUICKSTART_C} is missing"
    blocks = fenced_blocks(README.read_text(), "c")
    assert blocks, "README.md has no ```c block: it should show cpp-harness/examples/quickstart.c verbatim"
    want = normalized(QUICKSTART_C.read_text())
    for i, block in enumerate(blocks):
        assert normalized(block) == want, f"README.md ```c block {i + 1} differs from cpp-harness/examples/quickstart.c"


@pytest.mark.parametrize(
    "text,lang,expected",
    [
        ("a\n```python\nx = 1\n```\nb\n```c\nint a;\n```\n```python\ny\n```\n", "python", ["x = 1\n", "y\n"]),
        ("```c\nint a;\n```\n```cpp\nint b;\n```\n", "c", ["int a;\n"]),
        ("no blocks", "python", []),
    ],
)
def test_fenced_block_parser(text, lang, expected):
    assert fenced_blocks(text, lang) == expected
