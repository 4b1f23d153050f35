"""One module per `dnarod` subcommand.

Each module defines NAME (the subcommand), HELP (one line), and
`add_arguments(parser)` and `run(args) -> int`. The CLI finds them here, so
adding a subcommand is adding a file.
"""
