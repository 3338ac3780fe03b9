"""The ``modal_table`` bridge kind: a bridge given by the CSV tables of its modes (docs/modal_bridge.md).

The dataclass only (its tables are read by :mod:`tb_exudyn.structure.imported`); ``model.py`` puts it
in the ``Bridge`` union.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .schema import ANY, POSITIVE, Context, Validated, described, param, replace
from .sections import Spanned, check_tracks, deck_width_param


@dataclass(frozen=True, kw_only=True)
class ModalTrack(Validated):
    """One track of a ``modal_table`` bridge: the shapes along its centre line at rail level (a CSV file in
    the format of ``shapes``), and where it lies (for ``show`` and the checks of the tracks' places)."""

    file_keys: ClassVar[tuple[str, ...]] = ("shapes",)
    shapes: str = param(doc="CSV file: x and y<k>, z<k>, rx<k> per mode k along this track (rail level)")
    offset: float = param(unit="m", doc="track centre line from the girder axis (+y left)", check=ANY)
    height: float = param(0.0, unit="m", doc="rail level above the girder shear centre", check=ANY)

    def _validate(self, ctx: Context) -> None:
        if not self.shapes:
            raise ctx.child("shapes").error("", "the name of a CSV file", "no file")

    def replace(self, **changes):
        return replace(self, **changes)


@dataclass(frozen=True, kw_only=True)
@described
class ModalTable(Validated, Spanned):
    """A bridge given by its modes: frequencies, damping ratios and mass-normalised shapes in CSV
    tables written by any FE program (format: docs/modal_bridge.md; read by
    :mod:`tb_exudyn.structure.imported`). File names relative to the file this table is read from."""

    kind: ClassVar[str] = "modal_table"
    #: keys holding file names: made absolute against the file read (schema.from_dict)
    file_keys: ClassVar[tuple[str, ...]] = ("modes", "shapes", "stations")
    name: str = param(doc="identifier")
    spans: tuple[float, ...] = param(unit="m", doc="span lengths in running order (the deck stations' positions)",
                                     check=POSITIVE)
    modes: str = param(doc="CSV file: mode, frequency_hz, damping_ratio, type, modal_mass per mode")
    shapes: str = param("", doc="CSV file: x and y<k>, z<k>, rx<k> per mode k at the track line (rail level); or "
                                "[[tracks]], each with its own")
    tracks: tuple[ModalTrack, ...] = param((), doc="every track on the deck, track 1 first, each with its shapes file "
                                                   "(instead of shapes); the scenario's track.on picks the train's")
    deck_width: float = deck_width_param()
    stations: str = param("", doc="CSV file: station, x and y<k>, z<k>, rx<k> per output station ('': span "
                                  "quarter points and midspans on the track line)")

    #: no EN 1991-2 data (the code check refuses the bridge)
    code: ClassVar[None] = None

    def _validate(self, ctx: Context) -> None:
        self.check_spans(ctx)
        if not self.modes:
            raise ctx.child("modes").error("", "the name of a CSV file", "no file")
        if self.tracks and self.shapes:
            raise ctx.child("tracks").error(f"{len(self.tracks)} tracks", "either shapes (one track) or [[tracks]] "
                                            "tables, each with its shapes (every track), not both", "two track definitions")
        if not self.tracks and not self.shapes:
            raise ctx.child("shapes").error("", "the name of a CSV file (or [[tracks]] with theirs)", "no file")
        check_tracks(self, ctx)

    def replace(self, **changes):
        """A copy checked as the TOML loader checks (:func:`.schema.replace`)."""
        return replace(self, **changes)
