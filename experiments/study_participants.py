"""Run the study's `participants` part alone (always, even if finished).

Its logic and what it writes: src/ergohandover/study/parts/participants.py (printed by --help).
The whole study: experiments/run_all.py.

Usage: python experiments/study_participants.py [--config FILE] [--set KEY=VALUE] [--results DIR]
       [--workers N] [--engine local|ray] [--address auto|HOST:PORT]
"""

from ergohandover.study.parts import participants
from ergohandover.study.script import study_main

if __name__ == "__main__":
    study_main("participants", participants.__doc__)
