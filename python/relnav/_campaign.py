"""Monte Carlo campaigns of the evaluation engine, on this machine's threads or on a Dask
cluster, bit-identical to ``relnav simulate`` on the same scenario.

A campaign of R runs is cut into the engine's fixed chunks of 4 runs (run i seeded from
the scenario's seed and i alone). Each chunk runs anywhere — a local thread, or a task on
a Dask worker — and returns its partial sums as bytes; the driver adds them *in chunk
order*, exactly as the CLI's runner does, so the floating-point sums and every number of
the result are the same whatever the number of threads, workers or machines.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Mapping
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from pathlib import Path
from typing import Any, Iterable, Iterator, Optional, Sequence, Tuple, Union

from . import _relnav
from .errors import InvalidArgumentError

__all__ = ["campaign", "scenario_text"]

ScenarioSource = Union[str, "os.PathLike[str]", Mapping]


def scenario_text(scenario: ScenarioSource) -> str:
    """The TOML text of a scenario, validated: a path to a ``.toml`` file, the name of a
    built-in scenario (``paper000``, ``paper003``, ... as ``relnav scenarios`` lists
    them), TOML text, or a dict with the file's structure (e.g. from ``tomllib``)."""
    if isinstance(scenario, Mapping):
        return _relnav.scenario_toml(dict(scenario))
    if isinstance(scenario, (str, os.PathLike)):
        text = os.fspath(scenario)
        if "\n" not in text:
            path = Path(text)
            if path.is_file():
                text = path.read_text(encoding="utf-8")
            else:
                builtin = _relnav.builtin_scenario(text)
                if builtin is None:
                    raise InvalidArgumentError(
                        f"scenario {text!r} is neither a file nor a built-in scenario "
                        f"(built-in: {', '.join(_relnav.builtin_scenarios())})"
                    )
                text = builtin
        return _relnav.scenario_toml(text)
    raise InvalidArgumentError(
        f"scenario must be a path, a built-in name, TOML text or a dict (got {type(scenario).__name__})"
    )


@functools.lru_cache(maxsize=4)
def _prepared(text: str, runs: int) -> "_relnav._Campaign":
    """The prepared campaign, once per worker process (preparing may design H-infinity
    filters)."""
    return _relnav._Campaign(text, runs)


def _run_chunks(text: str, runs: int, indices: Sequence[int]) -> list:
    """A Dask task: run these chunks (consecutive indices) and return their partial sums."""
    c = _prepared(text, runs)
    return [c.run_chunk(i) for i in indices]


def _groups(n_chunks: int, per_task: int) -> list:
    return [list(range(s, min(s + per_task, n_chunks))) for s in range(0, n_chunks, per_task)]


def _progress(enabled: bool, total: int, desc: str):
    if not enabled:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, unit="run")


def _fold(
    camp: "_relnav._Campaign",
    results: Iterator[Tuple[Sequence[int], Sequence[bytes]]],
    bar,
) -> "_relnav.CampaignResult":
    """Add the partial sums in chunk order as they arrive (out-of-order ones wait)."""
    reducer = camp.reducer()
    chunks = camp.chunks
    waiting: dict = {}
    for indices, parts in results:
        for i, p in zip(indices, parts):
            waiting[i] = p
            if bar is not None:
                bar.update(chunks[i][1] - chunks[i][0])
        while reducer.next_index in waiting:
            reducer.add(waiting.pop(reducer.next_index))
    return reducer.finish()


def _local(camp, threads: int, per_task: int) -> Iterator[Tuple[Sequence[int], Sequence[bytes]]]:
    groups = _groups(len(camp.chunks), per_task)
    with ThreadPoolExecutor(max_workers=threads, thread_name_prefix="relnav") as pool:
        pending = {pool.submit(lambda g=g: [camp.run_chunk(i) for i in g]): g for g in groups}
        try:
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for f in done:
                    yield pending.pop(f), f.result()
        finally:
            for f in pending:
                f.cancel()


def _dask(client, text: str, camp, per_task: int) -> Iterator[Tuple[Sequence[int], Sequence[bytes]]]:
    from distributed import as_completed

    groups = _groups(len(camp.chunks), per_task)
    futures = [
        client.submit(_run_chunks, text, camp.runs, g, pure=False, key=f"relnav-{camp.name}-chunks-{g[0]}-{os.urandom(4).hex()}")
        for g in groups
    ]
    index = {f.key: g for f, g in zip(futures, groups)}
    try:
        for f, parts in as_completed(futures, with_results=True):
            yield index[f.key], parts
    finally:
        # on an error or Ctrl-C: stop what has not run yet
        client.cancel([f for f in futures if not f.done()])


def campaign(
    scenario: ScenarioSource,
    runs: Optional[int] = None,
    client: Any = None,
    *,
    threads: Optional[int] = None,
    chunks_per_task: int = 1,
    progress: bool = True,
) -> "_relnav.CampaignResult":
    """Run the evaluation engine's Monte Carlo campaign of ``scenario`` and return its
    :class:`CampaignResult`: ``summary`` (the numbers of the CLI's ``summary.csv``, one
    dict per filter), ``timeseries`` (the columns of ``timeseries.csv``), ``markdown()``,
    ``write_csv(dir)``, ``write_plots(dir)``.

    ``scenario``: a scenario file, a built-in name (``"paper003"``), TOML text or a dict.
    ``runs``: the number of runs (default: the file's ``simulation.runs``).
    ``client``: a ``dask.distributed.Client``; each task runs ``chunks_per_task`` of the
    engine's chunks of 4 runs on a worker (the workers need this same ``relnav``
    installed). Without a client the chunks run on ``threads`` local threads (default:
    one per core). ``progress`` shows a tqdm bar counting runs.

    Whatever the client, threads or workers, the result is bit-identical to ``relnav
    simulate FILE --runs R`` (only ``us_per_step``, a wall-clock time, differs).
    """
    if runs is not None and (isinstance(runs, bool) or not isinstance(runs, int) or runs < 1):
        raise InvalidArgumentError(f"runs must be a positive integer (got {runs!r})")
    if not isinstance(chunks_per_task, int) or chunks_per_task < 1:
        raise InvalidArgumentError(f"chunks_per_task must be a positive integer (got {chunks_per_task!r})")
    text = scenario_text(scenario)
    camp = _relnav._Campaign(text, runs)
    bar = _progress(progress, camp.runs, camp.name)
    try:
        if client is None:
            n = threads if threads is not None else (os.cpu_count() or 1)
            if not isinstance(n, int) or n < 1:
                raise InvalidArgumentError(f"threads must be a positive integer (got {threads!r})")
            results: Iterable = _local(camp, n, chunks_per_task)
        else:
            results = _dask(client, text, camp, chunks_per_task)
        return _fold(camp, iter(results), bar)
    finally:
        if bar is not None:
            bar.close()
