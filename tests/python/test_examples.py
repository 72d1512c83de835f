"""The quick-start examples run, and the README and the guides under docs/ show them
verbatim: every ```python block is an examples/*.py file, every ```c block a
cpp-harness/examples/*.c file, every `cc` command builds and runs, and every shell command
of the README is one the test suite runs."""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO_ROOT

QUICKSTART_PY = REPO_ROOT / "examples" / "fmpy_quickstart.py"
QUICKSTART_C = REPO_ROOT / "cpp-harness" / "examples" / "quickstart.c"
README = REPO_ROOT / "README.md"
DOCS = [README, *sorted((REPO_ROOT / "docs").glob("*.md"))]
C_EXAMPLES = REPO_ROOT / "cpp-harness" / "examples"
# which examples each page must show (verbatim, in a fenced block of its language)
SHOWN = {
    "README.md": ["fmpy_quickstart.py", "relnav_python_quickstart.py", "quickstart.c"],
    "docs/python.md": ["relnav_campaign.py"],
    "docs/c-abi.md": ["save_restore.c"],
}
# Every shell command of the README and what runs it. A command added to the README needs
# a line here, and the line says where the suite runs it.
README_COMMANDS = {
    "bash scripts/main.sh": "the main job itself; its stages are setup.sh, fmu/build.sh (both run by "
    "scripts/test.sh), tools/paper000_fmu.py, relnav reproduce and tools/relnav_system.py",
    "bash scripts/test.sh": ".ci/run",
    "bash fmu/build.sh -j2": "scripts/test.sh, stage 'build FMUs' (-j$RELNAV_JOBS, 2 by default)",
    ".venv/bin/python examples/fmpy_quickstart.py": "test_fmpy_quickstart_runs",
    "cargo build --release": "scripts/test.sh, stage 'cargo build --release'",
    "cc -Iinclude cpp-harness/examples/quickstart.c target/release/librelnav.a -lpthread -ldl -lm -o quickstart "
    "&& ./quickstart": "test_doc_cc_commands_build_and_run",
    ".venv/bin/python examples/relnav_python_quickstart.py": "test_package_api.py::test_readme_example_runs",
    "bash scripts/build-flight.sh": "scripts/test.sh, stage 'flight library'",
    "cc -Iinclude cpp-harness/examples/quickstart.c target/flight/librelnav.a -lm -o quickstart_flight "
    "&& ./quickstart_flight": "test_doc_cc_commands_build_and_run",
}


def rel(path) -> str:
    return path.relative_to(REPO_ROOT).as_posix()


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
    """Every ```python block of README.md and docs/*.md is one of examples/*.py verbatim,
    and each page shows the examples SHOWN lists (the Python package's examples run in
    test_package_api.py and test_package_campaign.py)."""
    assert README.is_file(), "README.md is missing"
    examples = {p.name: normalized(p.read_text()) for p in sorted((REPO_ROOT / "examples").glob("*.py"))}
    for doc in DOCS:
        shown = set()
        for i, block in enumerate(fenced_blocks(doc.read_text(), "python")):
            match = [name for name, text in examples.items() if text == normalized(block)]
            assert match, f"{rel(doc)} ```python block {i + 1} is none of examples/*.py verbatim"
            shown.update(match)
        for name in SHOWN.get(rel(doc), []):
            if name.endswith(".py"):
                assert name in shown, f"{rel(doc)} should show examples/{name} verbatim in a ```python block"
    for page in SHOWN:
        assert (REPO_ROOT / page).is_file(), f"{page} is missing"


def test_readme_c_blocks_are_the_c_quickstart():
    assert README.is_file(), "README.md is missing"
    assert QUICKSTART_C.is_file(), f"{QUICKSTART_C} is missing"
    blocks = fenced_blocks(README.read_text(), "c")
    assert blocks, "README.md has no ```c block: it should show cpp-harness/examples/quickstart.c verbatim"
    want = normalized(QUICKSTART_C.read_text())
    for i, block in enumerate(blocks):
        assert normalized(block) == want, f"README.md ```c block {i + 1} differs from cpp-harness/examples/quickstart.c"


def test_doc_c_blocks_are_the_c_examples():
    """Every ```c block of docs/*.md is one of cpp-harness/examples/*.c verbatim (ctest
    builds and runs each of them), and each page shows the C examples SHOWN lists."""
    examples = {p.name: normalized(p.read_text()) for p in sorted(C_EXAMPLES.glob("*.c"))}
    for doc in DOCS:
        shown = set()
        for i, block in enumerate(fenced_blocks(doc.read_text(), "c")):
            match = [name for name, text in examples.items() if text == normalized(block)]
            assert match, f"{rel(doc)} ```c block {i + 1} is none of cpp-harness/examples/*.c verbatim"
            shown.update(match)
        for name in SHOWN.get(rel(doc), []):
            if name.endswith(".c"):
                assert name in shown, f"{rel(doc)} should show cpp-harness/examples/{name} verbatim in a ```c block"


def test_doc_cmake_blocks_are_excerpts_of_the_harness():
    """Every ```cmake block of docs/*.md is a run of consecutive lines of
    cpp-harness/CMakeLists.txt, which builds the harness's tests and examples."""
    lines = (REPO_ROOT / "cpp-harness" / "CMakeLists.txt").read_text().splitlines()
    for doc in DOCS:
        for i, block in enumerate(fenced_blocks(doc.read_text(), "cmake")):
            want = block.strip("\n").splitlines()
            n = len(want)
            assert any(lines[k:k + n] == want for k in range(len(lines) - n + 1)), (
                f"{rel(doc)} ```cmake block {i + 1} is not an excerpt of cpp-harness/CMakeLists.txt"
            )


def shell_commands(text: str) -> list[str]:
    """The commands of every ```sh block: one per line, comments and blank lines dropped."""
    out = []
    for block in fenced_blocks(text, "sh"):
        for line in block.splitlines():
            cmd = line.split("#", 1)[0].strip() if not line.lstrip().startswith("#") else ""
            if cmd:
                out.append(cmd)
    return out


def test_readme_shell_commands_are_exercised():
    commands = shell_commands(README.read_text())
    assert "bash scripts/main.sh" in commands[:2] and "bash scripts/test.sh" in commands[:2], commands[:2]
    for cmd in commands:
        assert cmd in README_COMMANDS, f"README.md runs `{cmd}`: add it to README_COMMANDS with the test that runs it"
    for script in ("scripts/main.sh", "scripts/test.sh", "fmu/build.sh"):
        assert (REPO_ROOT / script).is_file(), script
    for example in ("examples/fmpy_quickstart.py", "examples/relnav_python_quickstart.py"):
        assert (REPO_ROOT / example).is_file(), example


def target_dir():
    return Path(os.environ.get("CARGO_TARGET_DIR") or REPO_ROOT / "target")


def test_doc_cc_commands_build_and_run(tmp_path):
    """Every `cc` line in a ```sh block of the README and docs/*.md compiles its example
    against the built library and runs it, from a directory laid out like the repository
    root (include/, cpp-harness/, target/)."""
    lines = [(rel(doc), cmd) for doc in DOCS for cmd in shell_commands(doc.read_text()) if cmd.startswith("cc ")]
    assert any(doc == "README.md" for doc, _ in lines), "README.md has no cc command"
    lib = target_dir() / "release"
    if not (lib / "librelnav.a").is_file() or not (lib / "librelnav.so").is_file():
        pytest.fail(f"{lib}/librelnav.a or .so missing: build them with `cargo build --release` "
                    "(scripts/test.sh does)", pytrace=False)
    (tmp_path / "include").symlink_to(REPO_ROOT / "include")
    (tmp_path / "cpp-harness").symlink_to(REPO_ROOT / "cpp-harness")
    (tmp_path / "target").symlink_to(target_dir())
    for doc, cmd in lines:
        proc = subprocess.run(["bash", "-c", cmd], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, f"{doc}: `{cmd}` failed:\n{proc.stdout}{proc.stderr}"
        example = Path(next(w for w in shlex.split(cmd) if w.endswith(".c"))).name
        if example == "quickstart.c":
            pos = re.search(r"position \[m\] +([-\d.]+) +([-\d.]+) +([-\d.]+)", proc.stdout)
            assert pos, proc.stdout
            n = 2 * np.pi / 7200  # truth at t = 1 s, paper 000's closed form (at rest at t = 0)
            truth = np.array([400 + 3000 * (np.sin(n) - n), 500 * (4 - 3 * np.cos(n)), 200 * np.cos(n)])
            assert np.all(np.abs(np.array([float(v) for v in pos.groups()]) - truth) < 1.0), proc.stdout
        elif example == "save_restore.c":
            assert "continued after restore: bit for bit" in proc.stdout, proc.stdout
            assert "into an EKF: invalid saved state" in proc.stdout, proc.stdout


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
