"""How honest were a study run's time promises? Reads the log of a run_all.py run (its standard
output and error, e.g. ``python experiments/run_all.py --force > run.log 2>&1``) and prints:

- each part's estimate (the line run_all prints at its start) beside its measured time;
- the whole run's estimate beside its measured time, as a ratio (the target: 0.7-1.3);
- the learning part's progress bar: the largest time left it showed after its first minute,
  as a multiple of the part's final time (the target: at most 3).

Usage: python experiments/tools/check_progress.py RUN.LOG
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

DURATION = r"(\d+(?:\.\d+)?) (s|min)"
BAR = re.compile(r"^learning \(\d+/\d+ runs\):.*\[(?P<elapsed>[\d:]+)<(?P<left>[\d:?]+)\]")


def seconds(value: str, unit: str) -> float:
    return float(value) * (60 if unit == "min" else 1)


def clock(text: str) -> float | None:
    """tqdm's ``[H:]MM:SS`` in seconds; None for ``?``."""
    if "?" in text:
        return None
    total = 0.0
    for part in text.split(":"):
        total = 60 * total + int(part)
    return total


def parse(log: str) -> dict:
    lines = [line for chunk in log.splitlines() for line in chunk.split("\r")]
    estimates, measured, bar = {}, {}, []
    total_estimate = total_measured = None
    for line in lines:
        if line.startswith("run_all (") and "estimated" in line:
            head, _, parts = line.partition(": ")[2].partition("estimated ")[2].partition(": ")
            total_estimate = seconds(*re.match(DURATION, head).groups())
            for name, value, unit in re.findall(r"(\w+) " + DURATION, parts):
                estimates[name] = seconds(value, unit)
        elif match := re.match(r"^   (\w+): (\d+) s$", line):
            measured[match[1]] = float(match[2])
        elif match := re.match(r"^run_all done in " + DURATION, line):
            total_measured = seconds(match[1], match[2])
        elif match := BAR.match(line):
            elapsed, left = clock(match["elapsed"]), clock(match["left"])
            if left is not None:
                bar.append((elapsed, left))
    return {"estimates": estimates, "measured": measured, "bar": bar,
            "total_estimate": total_estimate, "total_measured": total_measured}


def report(found: dict) -> bool:
    """Print the comparison; True when both targets hold."""
    print(f"{'part':<14}{'estimated':>11}{'measured':>10}{'ratio':>7}")
    for name, measured in found["measured"].items():
        estimate = found["estimates"].get(name)
        ratio = f"{estimate / measured:7.2f}" if estimate and measured else "      –"
        shown = f"{estimate:10.0f}s" if estimate is not None else "  finished"
        print(f"{name:<14}{shown}{measured:9.0f}s{ratio}")
    ok = True
    if found["total_estimate"] and found["total_measured"]:
        ratio = found["total_estimate"] / found["total_measured"]
        ok &= 0.7 <= ratio <= 1.3
        print(f"whole run: estimated {found['total_estimate'] / 60:.1f} min, measured "
              f"{found['total_measured'] / 60:.1f} min: ratio {ratio:.2f} (target 0.7-1.3)")
    final = found["measured"].get("learning")
    late = [(e, left) for e, left in found["bar"] if e >= 60]
    if final and late:
        worst_elapsed, worst = max(late, key=lambda item: item[1])
        ok &= worst <= 3 * final
        print(f"learning bar: {len(found['bar'])} updates; after its first minute the largest "
              f"time left shown was {worst:.0f} s (at {worst_elapsed:.0f} s), "
              f"{worst / final:.2f}x the part's {final:.0f} s (target at most 3x)")
    return ok


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("log", type=Path, help="the run's log (standard output and error)")
    args = parser.parse_args(argv)
    try:
        text = args.log.read_text(errors="replace")
    except OSError as exc:
        parser.error(f"{args.log}: {exc.strerror}")
    return 0 if report(parse(text)) else 1


if __name__ == "__main__":
    sys.exit(main())
