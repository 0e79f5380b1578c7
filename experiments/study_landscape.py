"""Run the study's `landscape` part alone (always, even if finished).

Its logic and what it writes: src/ergohandover/study/parts/landscape.py (printed by --help).
The whole study: experiments/run_all.py.

Usage: python experiments/study_landscape.py [--config FILE] [--set KEY=VALUE] [--results DIR]
       [--workers N] [--engine local|ray] [--address auto|HOST:PORT]
"""

from ergohandover.study.parts import landscape
from ergohandover.study.script import study_main

if __name__ == "__main__":
    study_main("landscape", landscape.__doc__)
