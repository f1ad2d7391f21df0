"""The ``planner`` command line: parsing and printing only (one module per concern).

- :mod:`planner.cli.main`: the entry point (:func:`main`: exit codes, one-line errors);
- :mod:`planner.cli.parser` and :mod:`planner.cli.parsers`: the subcommands' parsers, one module each;
- :mod:`planner.cli.tuning`: the tuning keys (one table: type, default, help); :mod:`planner.cli.profile`: how
  they are set (``--set KEY=VALUE``, ``--config FILE``) and listed (``--help-all``);
- :mod:`planner.cli.commands`, :mod:`planner.cli.network_command`: the commands (read, call the library, print);
  :mod:`planner.cli.inputs`: the site and files they read;
- :mod:`planner.cli.tiles`, :mod:`planner.cli.field`, :mod:`planner.cli.report`: the large-site, field-sheet
  and report parts; :mod:`planner.cli.option_types`, :mod:`planner.cli.choices`: checked option values.
"""

from planner.cli.main import build_parser, main

__all__ = ["build_parser", "main"]
