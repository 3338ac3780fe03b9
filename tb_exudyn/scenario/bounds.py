"""Physical bounds of scenario values that the field checks (:func:`.schema.param`) cannot state:
limits that keep a model from being degenerate, stated with their reason."""

from __future__ import annotations

from typing import Any

from .schema import Context

#: physical bounds of a span [m]: a shorter one is no beam (its modes lie far above any analysed band:
#: a 1 m span of the reference girder has its first mode at about 5 kHz), a longer one is longer than
#: any bridge span built (the longest, 2023 m, is a suspension bridge's main span)
SPAN_RANGE = (1.0, 2500.0)


def check_spans(bridge: Any, ctx: Context) -> None:
    """A bridge's ``spans``: at least one, each within :data:`SPAN_RANGE` (ScenarioError naming ``spans[i]``)."""
    if not bridge.spans:
        raise ctx.child("spans").error([], "at least one span length > 0", "no spans")
    for i, span in enumerate(bridge.spans):
        if not SPAN_RANGE[0] <= span <= SPAN_RANGE[1]:
            raise ctx.child("spans").child(i).error(span, f"{SPAN_RANGE[0]:g} m <= span <= {SPAN_RANGE[1]:g} m",
                                                    "no bridge span")


__all__ = ["SPAN_RANGE", "check_spans"]
