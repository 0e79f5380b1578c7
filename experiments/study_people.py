"""Run the study's `people` part alone (always, even if finished).

Its logic and what it writes: src/ergohandover/study/parts/people.py (printed by --help).
The whole study: experiments/run_all.py.

Usage: python experiments/study_people.py [--config FILE] [--set KEY=VALUE] [--results DIR]
       [--workers N] [--engine local|ray] [--address auto|HOST:PORT]
"""

from ergohandover.study.parts import people
from ergohandover.study.script import study_main

if __name__ == "__main__":
    study_main("people", people.__doc__)
