"""A Monte Carlo campaign on a Dask cluster with the relnav Python package.

    python examples/relnav_campaign.py [SCENARIO [RUNS [SCHEDULER]]]

SCENARIO is a scenario file or a built-in name (default paper003), RUNS the number of
runs (default: the file's), SCHEDULER a running scheduler's address such as
tcp://10.0.0.5:8786 (default: a local cluster of 2 worker processes). The result is
bit-identical to `relnav simulate SCENARIO --runs RUNS`, however many workers run it.
"""
import sys

from dask.distributed import Client, LocalCluster

import relnav

if __name__ == "__main__":
    scenario = sys.argv[1] if len(sys.argv) > 1 else "paper003"
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else None
    if len(sys.argv) > 3:
        client = Client(sys.argv[3])  # workers: `dask worker tcp://...` on other machines
    else:
        client = Client(LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None))
    with client:
        # each task is one chunk of 4 runs; the partial sums come back and are added in
        # run order, as the CLI adds them
        result = relnav.campaign(scenario, runs=runs, client=client)
    print(result.markdown())
    for row in result.summary:  # the numbers of summary.csv
        print(f"{row['label']}: position RMSE {row['rmse_pos_m']:.4g} m over {row['runs_used']} runs")
    print("wrote", *result.write_csv(f"results/{result.scenario}"))
