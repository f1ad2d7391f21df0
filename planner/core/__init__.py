"""What every stage shares: the errors and exit codes (:mod:`planner.core.errors`), argument checks
(:mod:`planner.core.checks`), progress reporting (:mod:`planner.core.progress`), text and JSON output
(:mod:`planner.core.text`) and file reading helpers (:mod:`planner.core.fileio`)."""
