"""What a personalisation session leaves at its end: the recommendation and how sure it is,
said on standard output, and its files (trials, recommendation, manifest)."""

from __future__ import annotations

import time
from pathlib import Path

from ..io.atomic import atomic_write_csv
from ..io.manifest import write_manifest


def ending(args, session, stopped: str) -> str:
    """How many trials were used and why the session ended, in words."""
    used = f"{len(session.trials)} of {args.trials} trials used"
    if stopped == "target":
        return f"{used}: --target {args.target:g} reached"
    return used + {"budget": "", "grid": ": every location of the grid tried",
                   "searcher": ": the searcher proposed only known locations"}[stopped]


def report(args, session, best, stopped: str, sure: dict) -> None:
    """The recommendation and how sure it is, on standard output."""
    from ..search.oracles import in_cm

    if best is None:
        print(f"no recommendation: the worker could take the box at none of the locations "
              f"tried; {ending(args, session, stopped)}", flush=True)
        return
    if args.answers == "pairwise":
        print(f"recommended: hand the box at {in_cm(best.location)}: the handover preferred "
              f"most (trial {best.trial.trial}); {ending(args, session, stopped)}", flush=True)
        chance = sure["p_best_of_tried"]
        said = ("no comparison was made" if chance is None else
                f"the preference model gives it a {chance:.0%} chance of being the best of the "
                f"{sure['feasible_tried']} feasible locations tried")
        print(f"uncertainty: {said}", flush=True)
        return
    seen = (f"{args.objective} {best.score:g}, observed at trial {best.trial.trial}"
            if best.trial is not None else "its model's optimum, not handed over there yet")
    print(f"recommended: hand the box at {in_cm(best.location)}: {seen}; "
          f"{ending(args, session, stopped)}", flush=True)
    if "p_optimal" in sure:
        print(f"uncertainty: its model gives it a {sure['p_optimal']:.0%} probability of being "
              "this worker's optimum", flush=True)
        return
    close = sure["within_1_of_it"]
    why = " (one answer is one measurement: with measurement error any may be as good)"
    print(f"uncertainty: {close} of the {sure['feasible_tried'] - 1} other feasible locations "
          f"tried scored within one point of it{why if close else ''}", flush=True)


def write_outputs(args, session, best, stopped: str, output: Path, settings: dict,
                  started: float, sure: dict) -> list[Path]:
    """trials.csv, recommendation.csv (when a location was feasible) and manifest.json (with
    ``settings``). With preferences, a trial's score is empty: its answer says how it
    compared."""
    import pandas as pd

    output.mkdir(parents=True, exist_ok=True)
    table = session.table()
    pairwise = args.answers == "pairwise"
    if pairwise:
        table["score"] = None
    paths = [atomic_write_csv(table, output / "trials.csv")]
    summary = {"trials_used": len(session.trials), "ended_by": stopped, "recommendation": None}
    if best is not None:
        x, y, z = best.location
        seen = best.trial is not None and not pairwise
        row = {"x": x, "y": y, "z": z, "objective": args.objective,
               "score": best.score if seen else None,
               "trial": None if best.trial is None else best.trial.trial,
               "trials_used": len(session.trials), "answers": args.answers, **sure}
        paths.append(atomic_write_csv(pd.DataFrame([row]), output / "recommendation.csv"))
        summary["recommendation"] = row
    config = {**settings, "oracle": args.oracle, "answers": args.answers,
              "answer_file": args.answer_file, "trials": args.trials,
              "target": args.target, "state": str(session.path), "output": str(output)}
    paths.append(write_manifest(output, config, seeds={"searcher": args.seed},
                                wall_time_s=time.perf_counter() - started,
                                extra={"summary": summary}))
    return paths
