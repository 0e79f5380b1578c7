"""Figure: the fatigue model's constants at a glance. Per joint, the time a
sustained load is held before the joint fails, from the three-compartment model's closed form
(Frey-Law et al. 2012's rates) as a line, beside the endurance power law fitted to published
endurance times (Frey-Law & Avin 2010) dashed, in its 95 % prediction band. Reads
results/shift/curves.csv (the report's tables are shift_tables.py's)."""

from __future__ import annotations

import matplotlib.pyplot as plt
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


if __name__ == "__main__":
    main()
