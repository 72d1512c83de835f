"""relnav.campaign gives `relnav simulate`'s result bit for bit: on local threads, on a
Dask LocalCluster of 2 worker processes (one chunk per task, or two), from the file or
from a dict, and through docs/python.md's campaign example. Only the wall-clock column
``us_per_step`` of summary.csv may differ.

A small campaign keeps this cheap: paper 000 cut to 60 s, three Kalman filters and one
particle filter with 200 particles, 10 runs (three chunks, the last one partial)."""

from __future__ import annotations

import csv
import logging
import math
import subprocess
import sys
import tomllib

import numpy as np
import pytest

import relnav
from conftest import REPO_ROOT

CLI = REPO_ROOT / "target" / "release" / "relnav"
EXAMPLE = REPO_ROOT / "examples" / "relnav_campaign.py"
RUNS = 10


def small_scenario() -> dict:
    d = tomllib.loads((REPO_ROOT / "scenarios" / "paper000.toml").read_text())
    d["name"] = "paper000_small"
    d["simulation"]["duration"] = 60.0
    d["filter"] = [f for f in d["filter"] if f["label"] in ("EKF", "UKF", "EKF (Euler, literal)", "RPF")]
    for f in d["filter"]:
        if "particles" in f:
            f["particles"] = 200
    return d


@pytest.fixture(scope="module")
def scenario_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenario") / "paper000_small.toml"
    path.write_text(relnav.scenario_text(small_scenario()))
    return path


def cli_result(scenario_file, out, runs=RUNS):
    if not CLI.is_file():
        pytest.fail(f"{CLI} missing: build it with `cargo build --release`", pytrace=False)
    proc = subprocess.run(
        [str(CLI), "simulate", str(scenario_file), "--runs", str(runs), "--out", str(out), "--no-plots", "--threads", "2"],
        capture_output=True, text=True, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return out / "paper000_small"


@pytest.fixture(scope="module")
def cli_dir(scenario_file, tmp_path_factory):
    return cli_result(scenario_file, tmp_path_factory.mktemp("cli"))


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def without_timing(rows):
    i = rows[0].index("us_per_step")
    return [r[:i] + r[i + 1:] for r in rows]


def assert_same_files(cli_dir, result, out):
    """The result's CSV files equal the CLI's byte for byte (summary: but for the
    wall-clock column), and its numbers are the CSV's numbers bit for bit."""
    result.write_csv(out)
    assert (out / "timeseries.csv").read_bytes() == (cli_dir / "timeseries.csv").read_bytes()
    summary = read_csv(cli_dir / "summary.csv")
    assert without_timing(read_csv(out / "summary.csv")) == without_timing(summary)
    header, rows = summary[0], summary[1:]
    assert [r["label"] for r in result.summary] == [r[0] for r in rows]
    for got, row in zip(result.summary, rows):
        assert list(got) == header
        for name, cell in zip(header, row):
            v = got[name]
            if name == "us_per_step":
                assert v > 0
            elif isinstance(v, str):
                assert v == cell
            elif cell == "":
                assert math.isnan(v), name
            else:
                assert float(cell) == v and type(v)(cell) == v, (name, cell, v)
    series = read_csv(cli_dir / "timeseries.csv")
    ts = result.timeseries
    assert list(ts) == series[0]
    for j, name in enumerate(series[0]):
        col = np.array([float(r[j]) if r[j] else np.nan for r in series[1:]])
        assert ts[name].tobytes() == col.tobytes(), name


def test_local_threads_equal_the_cli(cli_dir, scenario_file, tmp_path):
    r = relnav.campaign(scenario_file, runs=RUNS, threads=3, progress=False)
    assert r.runs == RUNS and not r.interrupted and r.scenario == "paper000_small"
    assert r.filters == ["EKF", "UKF", "EKF (Euler, literal)", "RPF"]
    assert_same_files(cli_dir, r, tmp_path / "threads")
    # the same scenario as a dict, on one thread, grouped two chunks per task
    r = relnav.campaign(small_scenario(), runs=RUNS, threads=1, chunks_per_task=2, progress=False)
    assert_same_files(cli_dir, r, tmp_path / "dict")
    assert "EKF" in r.markdown() and r.pcrlb.shape == (61, 6) and r.pcrlb_reason is None


def test_dask_local_cluster_of_two_processes_equals_the_cli(cli_dir, scenario_file, tmp_path):
    distributed = pytest.importorskip("distributed", reason="dask.distributed is in scripts/requirements.txt")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=logging.ERROR
    ) as cluster, distributed.Client(cluster) as client:
        r = relnav.campaign(scenario_file, runs=RUNS, client=client, progress=False)
        assert_same_files(cli_dir, r, tmp_path / "dask1")
        r = relnav.campaign(str(scenario_file), runs=RUNS, client=client, chunks_per_task=2, progress=True)
        assert_same_files(cli_dir, r, tmp_path / "dask2")
        # both worker processes ran chunks (each prepared the scenario once)
        prepared = client.run(lambda: __import__("relnav")._campaign._prepared.cache_info().currsize)
        assert len(prepared) == 2 and all(n >= 1 for n in prepared.values()), prepared


def test_partial_sums_are_added_in_order_only(scenario_file):
    from relnav import _relnav

    c = _relnav._Campaign(scenario_file.read_text(), RUNS)
    assert c.chunks == [(0, 4), (4, 8), (8, 10)]
    r = c.reducer()
    p1 = c.run_chunk(1)
    with pytest.raises(RuntimeError, match="expected chunk 0"):
        r.add(p1)
    r.add(c.run_chunk(0))
    r.add(p1)
    with pytest.raises(RuntimeError, match="truncated"):
        r.add(p1[:-3])
    res = r.finish()
    assert res.runs == 8 and res.interrupted
    with pytest.raises(relnav.InvalidArgumentError, match="chunk 3 does not exist"):
        c.run_chunk(3)


def test_bad_scenarios_raise(tmp_path):
    with pytest.raises(relnav.InvalidArgumentError, match=r"neither a file nor a built-in scenario \(built-in: paper000"):
        relnav.campaign("no_such_scenario", progress=False)
    d = small_scenario()
    d["simulation"]["durration"] = 1.0
    with pytest.raises(relnav.InvalidArgumentError, match="durration"):
        relnav.campaign(d, progress=False)
    with pytest.raises(relnav.InvalidArgumentError, match="runs must be a positive integer"):
        relnav.campaign(small_scenario(), runs=0, progress=False)
    assert "paper003" in relnav.scenarios()


def test_campaign_example_runs_on_a_local_cluster(scenario_file, tmp_path):
    """examples/relnav_campaign.py (shown verbatim in docs/python.md) on a 2-process
    LocalCluster: exit 0, a progress bar, the table, and the CLI's CSV numbers."""
    proc = subprocess.run(
        [sys.executable, str(EXAMPLE), str(scenario_file), "6"],
        cwd=tmp_path, capture_output=True, text=True, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "6/6" in proc.stderr, proc.stderr  # tqdm's bar counted the runs
    assert "| EKF |" in proc.stdout and "RPF" in proc.stdout, proc.stdout
    ours = tmp_path / "results" / "paper000_small"
    cli = cli_result(scenario_file, tmp_path / "cli", runs=6)
    assert (ours / "timeseries.csv").read_bytes() == (cli / "timeseries.csv").read_bytes()
    assert without_timing(read_csv(ours / "summary.csv")) == without_timing(read_csv(cli / "summary.csv"))
