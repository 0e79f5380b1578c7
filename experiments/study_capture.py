"""Run the study's `capture` part alone (always, even if finished).

Its logic and what it writes: src/ergohandover/study/parts/capture.py (printed by --help).
The whole study: experiments/run_all.py.

Usage: python experiments/study_capture.py [--config FILE] [--set KEY=VALUE] [--results DIR]
       [--workers N] [--engine local|ray] [--address auto|HOST:PORT]
"""

from ergohandover.study.parts import capture
from ergohandover.study.script import study_main

if __name__ == "__main__":
    study_main("capture", capture.__doc__)
