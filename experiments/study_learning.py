"""Study part `learning`: the paper's protocol — tabular Q-learning, 10 runs at a 2-minute and
10 at a 5-minute cap — and DQN, random search and hill-climbing on the same landscape and caps,
spread over the cores.

Usage: python experiments/study_learning.py [--config ...]

Each run stops at its cap or, with ``stop_at_global_min`` (default), as soon as it holds the
landscape's global minimum: no later step can lower the minimum it reports, so the paper's
measure (the minimum score per run) is unchanged, and the full protocol fits the time budget.
Writes results/learning/: runs.csv (one row per run), traces/<agent>_cap<S>_seed<K>.csv,
truth.csv (the landscape's minimum), manifest.json.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import study_landscape
from tqdm import tqdm

from ergohandover.envs.handover_env import HandoverEnv
from ergohandover.envs.scores import LandscapeScores
from ergohandover.executor import LocalExecutor
from ergohandover.io.atomic import atomic_write_csv
from ergohandover.landscape.cache import Landscape, landscape_path
from ergohandover.learning.runner import run_agent
from ergohandover.learning.search import exhaustive
from ergohandover.learning.trace import Budget
from ergohandover.study.parts import part_config, run_part, study_main

ROOT = Path(__file__).resolve().parents[1]
_SCORES: dict[tuple[str, str], LandscapeScores] = {}


def scores_for(path: Path, objective: str) -> LandscapeScores:
    """One score table per process, landscape file and objective."""
    key = (str(path), objective)
    if key not in _SCORES:
        _SCORES[key] = LandscapeScores(Landscape.load(path), objective)
    return _SCORES[key]


def one_run(job: dict) -> dict:
    """Run one agent once; returns its summary row and its trace."""
    scores = scores_for(Path(job["landscape"]), job["objective"])
    dqn = job["agent"] == "dqn"
    env = HandoverEnv(scores, observation="position" if dqn else "indices")
    budget = Budget(time_cap_s=job["cap_s"], stop_score=job["stop_score"])
    result, _ = run_agent(job["agent"], env, budget, job["seed"],
                          job.get("temperature", "fixed"))
    first_time, first_step = result.first_reached
    row = {k: v for k, v in job.items() if k not in ("landscape", "stop_score")}
    row.update(best_score=result.best_score, first_reached_s=first_time,
               first_reached_step=first_step, steps=result.steps, elapsed_s=result.elapsed_s,
               stopped_by=result.stopped_by, global_min=scores.minimum(),
               reached_global_min=result.best_score <= scores.minimum())
    return {"row": row, "trace": result.trace}


def run_jobs(jobs: list[dict], workers: int, desc: str) -> list[dict]:
    """Run jobs over ``workers`` processes, in job order; a progress bar on stderr."""
    out = []
    with tqdm(total=len(jobs), desc=desc, unit="run") as bar:
        for result in LocalExecutor(workers).map(one_run, jobs):
            out.append(result)
            bar.update()
    return out


def write_runs(done: list[dict], folder: Path) -> pd.DataFrame:
    """runs.csv and one trace CSV per run."""
    runs = pd.DataFrame([d["row"] for d in done])
    (folder / "traces").mkdir(parents=True, exist_ok=True)
    for d in done:
        r = d["row"]
        tag = "_".join(str(r[k]) for k in ("agent", "objective", "temperature") if k in r)
        atomic_write_csv(d["trace"], folder / "traces" / f"{tag}_cap{r['cap_s']}_seed{r['seed']}"
                                                         ".csv")
    atomic_write_csv(runs, folder / "runs.csv")
    return runs


def run(config: dict, results: Path, workers: int, force: bool = False) -> None:
    study_landscape.run(config, results, workers)  # reused when finished
    part = part_config(config, "learning")
    def work(folder: Path) -> dict:
        landscape = study_landscape.default_landscape(config, workers)
        landscape_file = landscape_path(landscape.key)
        truth = exhaustive(landscape, part["objective"])
        stop = truth.score if part["stop_at_global_min"] else None
        jobs = [{"agent": agent, "objective": part["objective"], "temperature": "fixed",
                 "cap_s": cap, "seed": seed, "landscape": str(landscape_file),
                 "stop_score": stop}
                for agent in part["agents"]
                for cap in (part["dqn_caps_s"] if agent == "dqn" else part["caps_s"])
                for seed in range(part["seeds"])]
        runs = write_runs(run_jobs(jobs, workers, "learning"), folder)
        atomic_write_csv(pd.DataFrame([{
            "objective": part["objective"], "global_min": truth.score,
            "n_at_min": len(truth.cells), "fraction_at_min": truth.fraction,
            "best_x": truth.location[0], "best_y": truth.location[1],
            "best_z": truth.location[2]}]), folder / "truth.csv")
        return {"runs": len(runs), "reached": int(runs["reached_global_min"].sum())}

    run_part("learning", results / "learning", part, work,
             seeds={"runs": part["seeds"]}, force=force)


if __name__ == "__main__":
    study_main(run, __doc__, ROOT)
