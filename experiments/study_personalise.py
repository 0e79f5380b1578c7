"""Run the study's `personalise` part alone (always, even if finished).

Its logic and what it writes: src/ergohandover/study/parts/personalise.py (printed by --help).
The whole study: experiments/run_all.py.

Usage: python experiments/study_personalise.py [--config FILE] [--set KEY=VALUE] [--results DIR]
       [--workers N] [--engine local|ray] [--address auto|HOST:PORT]
"""

from ergohandover.study.parts import personalise
from ergohandover.study.script import study_main

if __name__ == "__main__":
    study_main("personalise", personalise.__doc__)
