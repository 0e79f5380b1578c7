"""Figures of the shift question (the report's tables are shift_tables.py's).

shift_reference.png: the fatigue model's constants at a glance. Per joint, the time a sustained
load is held before the joint fails, from the three-compartment model's closed form (Frey-Law et
al. 2012's rates) as a line, beside the endurance power law fitted to published endurance times
(Frey-Law & Avin 2010) dashed, in its 95 % prediction band. Reads results/shift/curves.csv.

shift_capacity.png: what a practitioner reads at a glance. Per handover rate and hold, the
default worker's weakest joint's capacity over the 8-hour shift at the posture's optimum beside
the robot's shortest-distance locations (one per start), the line ending where a joint fails.
Reads results/shift/trace.csv and results/shift/locations.csv."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from common import caption, read, save


def main() -> None:
    curves = read("shift/curves.csv")
    joints = list(dict.fromkeys(curves["joint"]))
    fig, axes = plt.subplots(2, (len(joints) + 1) // 2, figsize=(12, 6), sharex=True,
                             sharey=True, squeeze=False)
    for ax, joint in zip(axes.ravel(), joints, strict=False):
        table = curves[(curves["joint"] == joint) & (curves["load"] >= 0.1)]
        load = 100 * table["load"]
        ax.fill_between(load, table["band_low_s"], table["band_high_s"], color="tab:orange",
                        alpha=0.2, label="power law's 95 % band")
        ax.plot(load, table["power_law_s"], "--", color="tab:orange",
                label="power law (published endurance times)")
        ax.plot(load, table["model_s"], color="tab:blue", label="three-compartment model")
        never = 100 * table["never_fails_below"].iloc[0]
        ax.axvline(never, color="0.5", lw=0.8)
        ax.set_title(f"{joint} (never fails below {never:.1f} %)", fontsize=9)
        ax.set_yscale("log")
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes.ravel()[len(joints):]:
        ax.axis("off")
    for ax in axes[-1]:
        ax.set_xlabel("sustained load [% of strength]")
    for ax in axes[:, 0]:
        ax.set_ylabel("time to failure [s]")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower right", fontsize=8, frameon=False,
               bbox_to_anchor=(0.98, 0.08))
    fig.suptitle(f"Each joint's endurance under a sustained load: the fatigue model beside the "
                 f"published power law (N = {len(joints)} joints; the power laws fitted to 369 "
                 "endurance times from 194 studies)", fontsize=10)
    caption(fig, "Model: Frey-Law, Looft & Heitsman 2012's rates (J Biomech 45:1803), closed "
                 "form. Power law: Frey-Law & Avin 2010 (Ergonomics 53:109), fitted to 10–100 % "
                 "of strength; band ±47 %, the widest of its joints' 95 % prediction bands. "
                 "Grey line: the load at and below which the model never fails.")
    save(fig, "shift_reference.png")
    capacity_figure()


def capacity_figure() -> None:
    trace = read("shift/trace.csv")
    where = read("shift/locations.csv")
    plans = list(dict.fromkeys(zip(trace["rate_per_min"], trace["hold_s"], strict=True)))
    holds = sorted({h for _, h in plans})
    rates = sorted({r for r, _ in plans})
    fig, axes = plt.subplots(len(holds), len(rates), figsize=(3.2 * len(rates),
                                                              2.8 * len(holds)),
                             sharex=True, sharey=True, squeeze=False)
    # The weakest joint at each moment (NaN once any joint has failed).
    weakest = trace.groupby(["rate_per_min", "hold_s", "location", "minute"], sort=False)[
        "capacity"].agg(lambda c: c.min() if c.notna().all() else float("nan")).reset_index()
    baselines = [n for n in dict.fromkeys(weakest["location"]) if n != "posture-optimal"]
    for ax in axes.ravel():
        ax.axis("off")
    for rate, hold in plans:
        ax = axes[holds.index(hold)][rates.index(rate)]
        ax.axis("on")
        here = weakest[(weakest["rate_per_min"] == rate) & (weakest["hold_s"] == hold)]
        for k, name in enumerate(baselines):
            line = here[here["location"] == name]
            ax.plot(line["minute"] / 60, 100 * line["capacity"], color="tab:orange", lw=0.9,
                    alpha=0.8, label="shortest distance (each start)" if k == 0 else None)
            if line["capacity"].isna().any():  # a joint fails: where its line ends
                last = line[line["capacity"].notna()].iloc[-1]
                ax.plot(last["minute"] / 60, 100 * last["capacity"], "x", color="tab:red",
                        ms=7, label="a joint fails" if "a joint fails" not in
                        ax.get_legend_handles_labels()[1] else None)
        line = here[here["location"] == "posture-optimal"]
        ax.plot(line["minute"] / 60, 100 * line["capacity"], color="tab:blue", lw=2,
                label="the posture's optimum")
        ax.axhline(80, color="0.4", ls="--", lw=0.8, label="80 % kept")
        rows = where[(where["rate_per_min"] == rate) & (where["hold_s"] == hold)
                     & where["location"].isin(baselines)]
        fails = np.isfinite(rows["shift_failure_min"]).sum()
        said = (f"{fails} of {len(rows)} shortest-distance fail\n(first after "
                f"{rows['shift_failure_min'].min():.0f} min)" if fails else
                "no shortest-distance location fails")
        ax.text(0.98, 0.04, said, transform=ax.transAxes, ha="right", va="bottom", fontsize=7)
        ax.set_title(f"{rate:g} a minute, {hold:g} s holds", fontsize=9)
        ax.set_ylim(0, 102)
        ax.grid(True, alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("hours into the shift")
    for ax in axes[:, 0]:
        ax.set_ylabel("weakest joint's capacity [%]")
    found = {}
    for ax in axes.ravel():
        found |= dict(zip(*reversed(ax.get_legend_handles_labels()), strict=True))
    fig.legend(list(found.values()), list(found), loc="lower center", ncol=4, fontsize=8,
               frameon=False, bbox_to_anchor=(0.5, -0.01))
    fig.suptitle("The 50th-percentile man's weakest joint (shoulder, elbow or low back) over an "
                 f"8-hour shift: the posture's optimum beside the {len(baselines)} "
                 "shortest-distance locations (N = 1 worker, one deterministic twin)",
                 fontsize=10)
    caption(fig, "Capacity: what the joint can still give, 1 − fatigued share, before each "
                 "handover (three-compartment model, Frey-Law et al. 2012; strength: Harbo et "
                 "al. 2012 and the twin's low back). A line ends where a joint fails the hold.")
    save(fig, "shift_capacity.png")


if __name__ == "__main__":
    main()
