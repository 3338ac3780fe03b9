"""Every hostile-input case, for the measurement of the issues' tables (tests/reliability/measure.py):
the cases of issue 15 (cases.py) and those of issues 25, 27, 29 and 30 by topic (cases_<topic>.py), each list
run by its own test file."""

from __future__ import annotations

from .cases import CASES
from .cases_bounds import CASES_BOUNDS
from .cases_cont import CASES_CONT
from .cases_en1991 import CASES_EN1991
from .cases_flags import CASES_FLAGS
from .cases_guards import CASES_GUARDS
from .cases_limits import CASES_LIMITS
from .cases_modal import CASES_MODAL
from .cases_results2 import CASES_RESULTS2
from .cases_sections import CASES_SECTIONS
from .cases_speedrule import CASES_SPEEDRULE
from .cases_stochastic import CASES_STOCHASTIC
from .cases_tracks import CASES_TRACKS
from .cases_writes import CASES_WRITES

ALL_CASES = [*CASES, *CASES_LIMITS, *CASES_WRITES, *CASES_RESULTS2, *CASES_BOUNDS, *CASES_GUARDS, *CASES_EN1991,
             *CASES_STOCHASTIC, *CASES_CONT, *CASES_MODAL,
             *CASES_SPEEDRULE, *CASES_FLAGS, *CASES_TRACKS, *CASES_SECTIONS]
