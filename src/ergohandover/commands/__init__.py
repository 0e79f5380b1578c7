"""One module per ``ergohandover`` sub-command: ``add_parser(subparsers)`` and ``run(args)``."""
