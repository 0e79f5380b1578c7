"""Benchmark: the population sweep on the local process pool and on Ray, with Ray's overhead
per task and a projection to larger workforces on a cluster.

Usage: python experiments/bench_population.py [--workforce 6] [--step 0.01] [--cores 16 64 256]

Sweeps a sampled workforce through the landscape door (``landscapes_of``: each worker's 1 cm
paper-code landscape, 92,783 locations, one task per worker) on four executors: the local pool
with 2 and 1 processes, and a new local Ray instance with 1 and 2 CPUs; then a second workforce
of the same size on the same executor (cold: the executor's workers just started; warm: the
same workers, new bodies). Prints the time to open each executor, both sweeps, workers/hour and
locations/s warm, and checks that every run gives the same landscapes. Then times trivial
tasks on both engines (the overhead per task, beside the local pool's in the same run) and
projects the wall time of 100 and 1,000 workers on clusters of N cores, stating its
assumptions. Figures, not a test: absolute times move with the machine's load; the ratios
between engines measured in one run are the steadier figures.
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time
from pathlib import Path

from ergohandover.executor import LocalExecutor
from ergohandover.landscape import checksum, landscapes_of
from ergohandover.landscape.grid import Grid, parse_boundary
from ergohandover.study.engines import RayExecutor
from ergohandover.study.workforce import Workforce, bodies, sample_workforce
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.evaluate import Evaluator, evaluate_arrays
from ergohandover.twin.task import TaskSpec

TRIVIAL_TASKS = 400


def _nothing(job: int) -> int:
    return job


def timed_sweeps(name: str, executor, grid: Grid, workforces: list[list[Evaluator]],
                 folder: Path) -> tuple[float, float, float, list[str]]:
    """Seconds to open the executor, to sweep one workforce into an empty cache (the
    executor's workers cold: Ray's import the package and load the compiled kernels on their
    first task), and to sweep another workforce of the same size (the workers warm, the bodies
    new: each task still solves its worker's warm-start lattice); the landscapes' checksums."""
    start = time.perf_counter()
    with executor:
        opened = time.perf_counter() - start
        times, sums = [], []
        for attempt, evaluators in zip(("cold", "warm"), workforces, strict=True):
            os.environ["ERGOHANDOVER_CACHE"] = str(folder / f"{name}_{attempt}")
            start = time.perf_counter()
            done = {f.index: f.landscape for f in landscapes_of(evaluators, grid,
                                                               executor=executor,
                                                               progress=False)}
            times.append(time.perf_counter() - start)
            sums += [checksum(done[i].arrays) for i in range(len(evaluators))]
    return opened, times[0], times[1], sums


def overhead_per_task(executor) -> float:
    """Seconds per trivial task, round trip, with the executor already open and warm."""
    with executor:
        list(executor.map(_nothing, range(20)))  # workers started and warm
        start = time.perf_counter()
        list(executor.map_unordered(_nothing, range(TRIVIAL_TASKS)))
        return (time.perf_counter() - start) / TRIVIAL_TASKS


def main() -> None:
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--workforce", type=int, default=6, help="workers (default: 6)")
    parser.add_argument("--step", type=float, default=0.01, help="grid step [m] (default 0.01)")
    parser.add_argument("--cores", type=int, nargs="+", default=[16, 64, 256],
                        help="cluster sizes of the projection (default: 16 64 256)")
    args = parser.parse_args()
    task = TaskSpec()
    workforces = [[Evaluator(b, task) for b in bodies(sample_workforce(Workforce(
        args.workforce, seed=seed)))] for seed in (2027, 2028)]
    evaluators = workforces[1]
    grid = Grid(parse_boundary("paper-code", BodySpec(), task), args.step)
    points = grid.size * len(evaluators)
    print(f"{len(evaluators)} workers x {grid.describe()} = {points:,} locations; "
          f"{os.cpu_count()} cores")
    folder = Path(tempfile.mkdtemp(prefix="ergohandover_bench_population_"))
    # The kernels compiled (or loaded from numba's cache) here first, so that the forked local
    # workers start warm; Ray's workers load them themselves (counted in their cold sweep).
    evaluate_arrays(grid.points(0, 10), Evaluator(BodySpec(), task))
    runs = {}
    print(f"  {'engine':20s} {'open':>6s} {'cold':>7s} {'warm':>7s}   warm: workers/h, "
          "locations/s")
    # The pool first: a one-process "pool" evaluates in this process, whose warm-start lattices
    # of these very workers a pool forked afterwards would inherit (and look faster).
    for name, make in (("local, 2 processes", lambda: LocalExecutor(2)),
                       ("local, 1 process", lambda: LocalExecutor(1)),
                       ("Ray, 1 CPU", lambda: RayExecutor(1)),
                       ("Ray, 2 CPUs", lambda: RayExecutor(2))):
        opened, cold, warm, sums = timed_sweeps(name.replace(" ", "_").replace(",", ""),
                                                make(), grid, workforces, folder)
        runs[name] = (warm, sums)
        print(f"  {name:20s} {opened:5.1f}s {cold:6.1f}s {warm:6.1f}s   "
              f"{3600 * len(evaluators) / warm:6.0f} workers/h, {points / warm:7,.0f} "
              "locations/s")
    identical = len({tuple(s) for _, s in runs.values()}) == 1
    print(f"  every engine gives the same landscapes: {'yes' if identical else 'NO'}")
    for cpus, ray, local in ((1, "Ray, 1 CPU", "local, 1 process"),
                             (2, "Ray, 2 CPUs", "local, 2 processes")):
        print(f"  Ray / local pool, {cpus} CPU{'s' if cpus > 1 else ''}, warm: "
              f"{runs[ray][0] / runs[local][0]:.2f}x the wall time")
    ray_task = overhead_per_task(RayExecutor(2))
    local_task = overhead_per_task(LocalExecutor(2))
    print(f"overhead per task (round trip of a trivial task, {TRIVIAL_TASKS} tasks, 2 CPUs): "
          f"Ray {1e3 * ray_task:.2f} ms, local pool {1e3 * local_task:.3f} ms "
          f"({ray_task / local_task:.0f}x)")
    per_worker = runs["Ray, 1 CPU"][0] / len(evaluators)  # one core's seconds a worker, warm
    print(f"projection (one task per worker, {per_worker:.1f} s of one core each as measured "
          f"here, plus Ray's {1e3 * ray_task:.1f} ms a task; tasks independent, so the cores "
          "fill in waves; cores as fast as these; the driver receives ~4.5 MB a worker and "
          "writes it to the cache (its chunks first, then the landscape), which a shared "
          "file system must keep up with; starting the cluster and its workers' first imports "
          "not counted):")
    for workers in (100, 1000):
        cells = ", ".join(f"{n} cores {math.ceil(workers / n) * (per_worker + ray_task) / 60:.1f}"
                          " min" for n in args.cores)
        print(f"  {workers:5d} workers: {cells}; this machine (2 cores) "
              f"{math.ceil(workers / 2) * per_worker / 3600:.1f} h")


if __name__ == "__main__":
    main()
