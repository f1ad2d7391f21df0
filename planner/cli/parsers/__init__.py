"""The ``planner`` parser, one module per subcommand (each with ``add_parser(sub, handlers)``) and the option
groups they share (:mod:`planner.cli.parsers.common`); ``report`` and ``field`` keep theirs beside their commands
(:mod:`planner.cli.report`, :mod:`planner.cli.field`)."""
