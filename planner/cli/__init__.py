"""The ``planner`` command line: parsing and printing only (one module per concern).

- :mod:`planner.cli.parser`: the subcommands, their options and help texts;
- :mod:`planner.cli.profile`: tuning options (hidden from ``--help``, ``--help-all``, ``--config FILE``);
- :mod:`planner.cli.commands`: the commands (read, call the library, print, exit codes);
- :mod:`planner.cli.tiles`, :mod:`planner.cli.field`, :mod:`planner.cli.report`: the large-site, field-sheet
  and report parts; :mod:`planner.cli.option_types`, :mod:`planner.cli.choices`: checked option values.
"""

from planner.cli.commands import build_parser, main

__all__ = ["build_parser", "main"]
