"""``python -m ergohandover.cli``: the same as the ``ergohandover`` command."""

import sys

from . import main

sys.exit(main())
