"""Figure: an accommodation zone for handover risk. (a) the share of the workforce whose posture is
acceptable (REBA and RULA within limits) at each location of the plane x = 0, error-free, with
the zone that serves the stated share; (b) the same as one measurement under an IMU-like error
model would judge it; (c) the share at each headline location, both ways, with 95 % bootstrap
intervals over workers. Reads results/accommodation/."""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np
from common import RESULTS, caption, read, save


def plane(cells, column: str):
    """The plane of cells nearest x = 0 as (z axis, y axis, values[y, z])."""
    middle = cells["x"].iloc[int(np.argmin(cells["x"].abs().to_numpy()))]
    rows = cells[np.isclose(cells["x"], middle)]
    table = rows.pivot_table(index="y", columns="z", values=column)
    return table.columns.to_numpy(), table.index.to_numpy(), table.to_numpy(), middle


def share_panel(ax, cells, column: str, share: float, recommended, title: str):
    z, y, values, middle = plane(cells, column)
    image = ax.pcolormesh(z, y, values, vmin=0, vmax=1, cmap="viridis", shading="nearest")
    if np.nanmax(values) >= share:
        ax.contour(z, y, values, levels=[share], colors="white", linewidths=1.5)
    ax.plot(recommended["z"], recommended["y"], "r*", ms=11, label="recommended (nominal optimum)")
    ax.set_xlabel(f"z, forward [m]   (plane x = {middle:+.2f} m)")
    ax.set_ylabel("y, height [m]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    return image


def main() -> None:
    cells = read("accommodation/cells.csv")
    at = read("accommodation/locations.csv")
    zone = read("accommodation/zone.csv").set_index("kind")
    config = json.loads((RESULTS / "accommodation" / "manifest.json").read_text())
    part = config["config"]["accommodation"]
    share = float(zone.loc["exact", "share"])
    workers = int(at["workers"].iloc[0])
    recommended = at[at["location"] == "nominal optimum"].iloc[0]
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.2), layout="constrained",
                             gridspec_kw={"width_ratios": [1, 1, 1.3]})
    share_panel(axes[0], cells, "exact_share", share, recommended,
                f"(a) suited, error-free (white: {share:.0%} of workers)")
    image = share_panel(axes[1], cells, "measured_share", share, recommended,
                        "(b) suited, as one IMU-like measurement judges it")
    fig.colorbar(image, ax=axes[1], shrink=0.9, label="share of the workforce suited")
    ax = axes[2]
    order = np.arange(len(at))
    for offset, kind, colour in ((-0.15, "exact", "tab:blue"), (0.15, "measured", "tab:orange")):
        ax.errorbar(at[f"{kind}_share"], order + offset,
                    xerr=[at[f"{kind}_share"] - at[f"{kind}_low"],
                          at[f"{kind}_high"] - at[f"{kind}_share"]],
                    fmt="o", color=colour, ms=4, label="error-free" if kind == "exact"
                    else "one IMU-like measurement")
    ax.axvline(share, color="grey", ls="--", lw=1)
    ax.set_yticks(order, at["location"], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlim(0, 1.02)
    ax.set_xlabel("share of the workforce suited")
    ax.set_title(f"(c) headline locations (N = {workers:,} workers)", fontsize=9)
    ax.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Accommodation zone: REBA <= {part['reba_max']} and RULA <= "
                 f"{part['rula_max']} for N = {workers:,} workers of the ANSUR II body model, "
                 f"every {100 * part['step']:g} cm", fontsize=10)
    caption(fig, f"Each worker's twin solved at every grid point; measured {part['draws']} times "
            "per point under the IMU-like error model (4 of its 15 SDs from Schall et al. 2016, "
            "the rest assumed; the same draws at every point of a worker). Error-free shares "
            "of workers; as measured, the mean share of measurements that pass a worker. "
            "Intervals: percentile bootstrap over workers "
            f"({part['bootstrap']:,} resamples). Error-free, {int(zone.loc['exact', 'cells'])} "
            f"points serve {share:.0%}; as measured, "
            f"{int(zone.loc['measured', 'cells'])} (the best serves "
            f"{zone.loc['measured', 'best_share']:.0%}).")
    save(fig, "accommodation.png")


if __name__ == "__main__":
    main()
