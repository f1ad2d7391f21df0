"""A site and the limits it is seen under (:class:`Sight`): every coverage matrix of a run is built from one, so one
object says which limits a number was computed under."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.targets import Targets, make_targets
from planner.coverage.visibility import SightLimits, sight_limits
from planner.instrument.models import Scanner
from planner.site.candidate import Candidate
from planner.site.model import Site
from planner.site.validate import ValidationReport, validate_site

#: the wall pieces of the network check, the field sheet and the station summaries, m
STATION_PIECE_M = 1.0


@dataclass(frozen=True, kw_only=True)
class Sight:
    """``site`` seen under ``limits`` (range, incidence, precision) by ``scanner``: the coverage of any stations of it.
    A run's sight is its resolved problem's (:func:`planner.plan.problem.resolve`); :meth:`of_site` makes one for a site
    checked alone."""

    site: Site
    limits: SightLimits
    scanner: Scanner

    @classmethod
    def of_site(
        cls, site: Site, *, incidence_3d: bool = False, precision: bool = True, combined: bool = False
    ) -> Sight:
        """The sight of ``site`` validated alone, under its own parameters: for checking stations (network,
        registration, field sheet) without a planning run; a run passes its problem's sight instead."""
        return sight_of(site, incidence_3d=incidence_3d, precision=precision, combined=combined)[1]

    @property
    def combined(self) -> bool:
        """Views add information (combined precision)."""
        return self.limits.precision is not None and self.limits.precision.combined

    def coverage(self, candidates: Sequence[Candidate], targets: Targets, *, step: str = "") -> CoverageProblem:
        """Which of ``candidates`` sees which of ``targets`` (:func:`planner.coverage.matrix.build_coverage`); ``step``:
        the name progress is reported under."""
        return build_coverage(self.site, candidates, targets, self.limits, step)

    def of_stations(self, stations: Sequence[Candidate], spacing_m: float = STATION_PIECE_M) -> CoverageProblem:
        """The coverage of a plan's stations on wall pieces of at most ``spacing_m``."""
        return self.coverage(stations, make_targets(self.site, spacing_m))


def sight_of(
    site: Site,
    *,
    incidence_3d: bool = False,
    precision: bool = True,
    combined: bool = False,
    validation: ValidationReport | None = None,
) -> tuple[ValidationReport, Sight]:
    """The validation of ``site`` (``validation`` when given, else validated here: the one place a site is validated for
    planning or checking) and its :class:`Sight` under the incidence and precision modes."""
    if validation is None:
        validation = validate_site(site)
    limits = sight_limits(validation, incidence_3d, precision, combined)
    return validation, Sight(site=site, limits=limits, scanner=validation.scanner)


def as_sight(site: Site | Sight, *, combined: bool = False) -> Sight:
    """``site`` itself when it is a :class:`Sight`, else :meth:`Sight.of_site` (with ``combined`` precision)."""
    return site if isinstance(site, Sight) else Sight.of_site(site, combined=combined)
