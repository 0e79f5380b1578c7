"""Figure: does the recommendation survive being measured? (a) each headline location's expected
paper score against the SD of the posture-measurement error, and under an IMU-like error model
(4 of its 15 SDs measured, the rest assumed); (b) the expected paper score under the robust
optimum's SD in the plane x = 0 (the screened cells), with the nominal and robust optima; (c)
which item scores of the nominal optimum change under error, and how often; (d) the regret of
the recommendations over the model variants and the workers. Reads results/robustness/."""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
from common import caption, integer_axis, read, save

# An item's column name in words: "rula_left_table_a" -> "RULA left Table A".
SCORE_PREFIX = {"reba": "REBA", "rula": "RULA", "paper": "paper score's"}
CAPITALISED = re.compile(r"\b(table|score) ([a-d])\b")


def item_words(item: str) -> str:
    prefix, _, rest = item.partition("_")
    words = rest.replace("_", " ")
    words = CAPITALISED.sub(lambda m: f"{m[1].capitalize()} {m[2].upper()}", words)
    if prefix == "rula" and words in ("left", "right"):  # a side's own score
        words = f"{words} side's score"
    return f"{SCORE_PREFIX.get(prefix, prefix)} {words}"


SHOWN = {"nominal optimum": "tab:blue", "robust optimum": "tab:green",
         "largest margin": "tab:cyan", "practice": "tab:red",
         "one-size mean": "tab:purple"}


def expected_against_sd(ax, locations, measured) -> None:
    """Panel (a); the measured IMU error model (``measured``: measured_locations.csv's rows
    of the headline model) stands at its own place right of the SDs."""
    paper = locations[locations["score"] == "paper_postural"]
    shortest = paper[paper["location"].str.startswith("shortest")]
    sds = sorted(paper["angle_sd_deg"].unique())
    band = shortest.groupby("angle_sd_deg")["mean"]
    ax.fill_between(sds, band.min(), band.max(), color="grey", alpha=0.3,
                    label=f"shortest distance ({shortest['location'].nunique()} starts)")
    for name, colour in SHOWN.items():
        rows = paper[paper["location"] == name].sort_values("angle_sd_deg")
        if rows.empty:
            continue
        ax.plot(rows["angle_sd_deg"], rows["mean"], "o-", color=colour, label=name, ms=4)
    imu = measured[measured["score"] == "paper_postural"]
    if len(imu):
        x = max(sds) + 3
        short = imu[imu["location"].str.startswith("shortest")]["mean"]
        ax.vlines(x, short.min(), short.max(), color="grey", lw=6, alpha=0.5)
        for name, colour in SHOWN.items():
            row = imu[imu["location"] == name]
            if len(row):
                ax.plot([x], row["mean"], "D", color=colour, ms=5)
        ax.set_xticks([*sds, x], [f"{sd:g}" for sd in sds] + ["IMU-\nlike"])
    ax.set_xlabel("posture-measurement error, SD of every angle [deg]; an IMU-like error model")
    ax.set_ylabel("expected paper score")
    draws = int(paper["draws"].iloc[0])
    ax.set_title(f"(a) expected score under error (N = {draws:,} draws per point)", fontsize=9)
    ax.legend(fontsize=7)


def expected_plane(ax, plane, locations, sd) -> None:
    y, z = np.sort(plane["y"].unique()), np.sort(plane["z"].unique())
    grid = np.full((len(y), len(z)), np.nan)
    grid[np.searchsorted(y, plane["y"]), np.searchsorted(z, plane["z"])] = plane["expected"]
    image = ax.pcolormesh(z, y, grid, shading="nearest", cmap="viridis")
    plt.colorbar(image, ax=ax, label=f"expected paper score at {sd:g} deg")
    for name, marker in (("nominal optimum", "o"), ("robust optimum", "*")):
        row = locations[locations["location"] == name].iloc[0]
        ax.scatter(row["z"], row["y"], marker=marker, s=90, color="white", edgecolor="black",
                   label=name, zorder=3)
    ax.set_xlabel("z, in front [m]")
    ax.set_ylabel("y, height [m]")
    ax.set_title(f"(b) the plane x = {plane['x'].abs().min():.3f} m (N = {len(plane):,} "
                 "screened cells)", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")


def item_flips(ax, flips, sds) -> None:
    nominal = flips[flips["location"] == "nominal optimum"]
    shown = nominal[nominal["angle_sd_deg"] == max(sds)].nlargest(12, "p_flip")["item"]
    width = 0.8 / len(sds)
    y = np.arange(len(shown))
    for k, sd in enumerate(sds):
        rows = nominal[nominal["angle_sd_deg"] == sd].set_index("item").loc[shown]
        ax.barh(y + k * width, rows["p_flip"], height=width, label=f"SD {sd:g} deg")
    ax.set_yticks(y + width * (len(sds) - 1) / 2, [item_words(i) for i in shown], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("share of measurements in which the item differs from its error-free value")
    ax.set_title(f"(c) the nominal optimum's items that change (N = {len(shown)} most "
                 "often)", fontsize=9)
    ax.legend(fontsize=7)


def regret_counts(ax, regret) -> None:
    paper = regret[(regret["score"] == "paper_postural") & (regret["variant"] != "default")
                   ].dropna(subset=["regret"])  # the default model has no regret by definition
    values = np.arange(int(paper["regret"].max()) + 1)
    groups = list(paper.groupby(["source", "recommendation"], sort=False))
    width = 0.8 / len(groups)
    for k, ((source, rec), rows) in enumerate(groups):
        counts = [(rows["regret"] == v).mean() for v in values]
        ax.bar(values + (k - (len(groups) - 1) / 2) * width, counts, width=width,
               label=f"{rec}, {source} (N = {len(rows)})")
    integer_axis(ax, "x", values)
    ax.set_xlabel("regret: paper score at the recommendation less the own optimum")
    ax.set_ylabel("share")
    ax.set_title("(d) regret over model variants (the default left out) and workers",
                 fontsize=9)
    ax.legend(fontsize=7)


def main() -> None:
    locations = read("robustness/locations.csv")
    flips = read("robustness/flips.csv")
    regret = read("robustness/regret.csv")
    plane = read("robustness/expected_landscape.csv")
    manifest_sd = 5.0 if 5.0 in set(locations["angle_sd_deg"]) else locations[
        "angle_sd_deg"].max()
    fig, axes = plt.subplots(2, 2, figsize=(13, 9.5))
    measured = read("robustness/measured_locations.csv")
    expected_against_sd(axes[0, 0], locations,
                        measured[measured["error_model"] == measured["error_model"].iloc[0]])
    expected_plane(axes[0, 1], plane, locations, manifest_sd)
    item_flips(axes[1, 0], flips, [sd for sd in (2.0, 5.0) if sd in set(flips["angle_sd_deg"])])
    regret_counts(axes[1, 1], regret)
    fig.tight_layout()
    caption(fig, "Every measured angle of the twin's posture carries independent Gaussian "
            "error of the SD shown (the robustness part's configuration), or (diamonds, right of "
            "panel a) an IMU-like error model per joint, biased and correlated (4 of its 15 SDs "
            "from Schall et al. 2016, the rest of it assumed); scores are REBA's, RULA's and the "
            "paper's own. Regret is against each variant's or worker's own grid optimum.")
    save(fig, "robustness.png")


if __name__ == "__main__":
    main()
