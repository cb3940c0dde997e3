"""Throughput of the ensemble backends, side by side in one run: runs per second (and
per core) for rayon on one thread and on every core, the plain Python loop, Dask on a
local cluster of two worker processes and, where it is installed, Ray with two CPUs;
and each cluster's cost per task.

Run (after ``maturin develop --release`` in python/wheel, with dask[distributed]):

    python python/bench_ensembles.py [runs] [repeats]

The scene is the arm dropped onto its shoulder limit (``RestingArm``), 5 s per run,
friction and restitution drawn uniformly. Times are medians over the repeats, with the
range; every backend's table is checked equal to rayon's.
"""

import os
import statistics
import sys
import time

import filippov
from filippov import ensembles


def timed(f, repeats):
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times), max(times), out


def arm_ensemble(runs, t_end=5.0):
    arm = filippov.RestingArm(m1=1.0, l1=1.0, m2=0.5, l2=0.7, fc=2.0, lim=-1.0, e=0.5)
    draws = {"fc": ("uniform", 0.5, 20.0), "e": ("uniform", 0.0, 0.9)}
    return arm.ensemble(t_end, parameters=draws, q0=[0.2, -0.5], samples=runs, seed=3)


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 4000
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    cores = os.cpu_count()
    ens = arm_ensemble(runs)
    reference = ensembles.run(ens)
    from dask.distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, Client(cluster) as client:
        rows = []
        for name, used, f in [
            ("rayon, one thread", 1, lambda: ensembles.run(ens, threads=1)),
            (f"rayon, all {cores} cores", cores, lambda: ensembles.run(ens)),
            ("Python loop", 1, lambda: ensembles.run(ens, "loop")),
            ("Dask, 2 workers", 2, lambda: ensembles.run(ens, "dask", client=client, chunk=runs // 8)),
        ]:
            med, lo, hi, table = timed(f, repeats)
            assert table.equals(reference), name
            rows.append((name, used, med, lo, hi))
        print(f"{runs} runs of the resting arm, {repeats} repeats, medians (range):")
        print("| backend | time [s] | runs/s | runs/s per core |")
        print("|---|---|---|---|")
        for name, used, med, lo, hi in rows:
            print(f"| {name} | {med:.3f} ({lo:.3f}–{hi:.3f}) | {runs / med:,.0f} | {runs / med / used:,.0f} |")
        tiny = arm_ensemble(400, t_end=1e-6)
        alone, _, _, _ = timed(lambda: ensembles.run(tiny, threads=1), repeats)
        overhead(
            "Dask", alone, timed(lambda: ensembles.run(tiny, "dask", client=client, chunk=1), repeats)
        )
    try:
        import ray
    except ImportError:
        print("Ray is not installed: no Ray rows.")
        return
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        ensembles.run(tiny, "ray", chunk=1)  # workers started before timing
        med, lo, hi, table = timed(lambda: ensembles.run(ens, "ray", chunk=runs // 8), repeats)
        assert table.equals(reference), "ray"
        print(f"| Ray, 2 CPUs | {med:.3f} ({lo:.3f}–{hi:.3f}) | {runs / med:,.0f} | {runs / med / 2:,.0f} |")
        overhead("Ray", alone, timed(lambda: ensembles.run(tiny, "ray", chunk=1), repeats))
    finally:
        ray.shutdown()


def overhead(name, alone, result):
    """The cost of a task: tasks of one near-empty run (t_end = 1 µs), 400 of them."""
    med, lo, hi, _ = result
    per_task = (med - alone) / 400 * 2
    print(
        f"{name}: 400 tasks of one 1-µs run took {med:.3f} s ({lo:.3f}–{hi:.3f}) on 2 workers "
        f"against {alone:.4f} s in one loop: {per_task * 1e3:.2f} ms per task per worker."
    )


if __name__ == "__main__":
    main()
