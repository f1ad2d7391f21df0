"""The ``planner`` command line: parsing and printing only (one module per concern).

- :mod:`planner.cli.main`: the entry point (:func:`main`: exit codes, one-line errors);
- :mod:`planner.cli.parser`: the subcommands' parsers; the settings they take are defined once in
  :mod:`planner.core.settings`, turned into flags and tuning keys by :mod:`planner.cli.tuning`, and set by
  ``--set KEY=VALUE`` and ``--config FILE`` and listed by ``--help-all`` (:mod:`planner.cli.profile`);
- :mod:`planner.cli.commands`, :mod:`planner.cli.network_command`: the commands (read, call the library, print);
  :mod:`planner.cli.inputs`: the site and files they read;
- :mod:`planner.cli.field`, :mod:`planner.cli.report`, :mod:`planner.cli.hours`: the field-sheet, report and
  field-time parts; :mod:`planner.cli.option_types`: checked option values.
"""

from planner.cli.main import build_parser, main

__all__ = ["build_parser", "main"]
