"""The bridge's modes for the EN 1991-2 check (:func:`tb_exudyn.codes.check.check`): every mode up to the
cut-off max(30 Hz, 1.5 f1, f3) of EN 1990 A2.4.4.2.1, f1 and f3 those of the vertical bending modes, found by
raising the modes' limit from FIRST_MODE_LIMIT_HZ until three vertical modes (or, for a short stiff span,
the first) lie below it, at most MODE_LIMIT_CAP_HZ. A bridge outside that range is refused naming the file
the user gave and what would be in range (no option of the check changes it)."""

from __future__ import annotations

import numpy as np

from ..structure import StructureError, modal_bridge
from . import en1991 as code

#: the first modes are computed up to this frequency, raised until three vertical modes are found [Hz]
FIRST_MODE_LIMIT_HZ = 60.0
MODE_LIMIT_CAP_HZ = 480.0


def vertical(mb) -> np.ndarray:  # noqa: ANN001
    """The indices of a ModalBridge's vertical bending modes."""
    return np.flatnonzero(np.array([t == "vertical" for t in mb.mode_types]))


#: what a bridge too stiff for the check's modes may be instead (no option of the check changes it)
OUT_OF_RANGE = "a longer or more flexible span"


def modes_for_check(bridge, err, label):  # noqa: ANN001, ANN202
    """The bridge's modes up to the cut-off: (ModalBridge, modes used, f1, f3, cutoff, basis). Every
    mode up to the cut-off is used, at the track line (``rail_shapes(x).z``: bending plus torsion
    times the track's offset, EN 1990 A2.4.4.2.1 'along each track'); f1 and f3 of the cut-off are
    those of the vertical bending modes. The modes are computed up to FIRST_MODE_LIMIT_HZ, doubled
    until three vertical modes (or, for a short stiff span, the first) lie below it, at most
    MODE_LIMIT_CAP_HZ. Errors name the bridge as ``label`` (the file or name the user gave)."""
    limit = FIRST_MODE_LIMIT_HZ
    while True:
        try:
            mb = modal_bridge(bridge, limit)
        except StructureError as exc:
            if exc.key == "max_frequency" and limit < MODE_LIMIT_CAP_HZ:  # no mode below the limit yet: raise it
                limit *= 2.0
                continue
            if exc.key == "max_frequency":  # not a setting of the check: the bridge is outside its range
                raise err("bridge", label, OUT_OF_RANGE, f"no mode below {MODE_LIMIT_CAP_HZ:g} Hz ({exc.allowed})"
                          ) from None
            raise err("bridge", label, "a bridge a modal model can be built of", str(exc)) from None
        vert = vertical(mb)
        f_v = mb.frequencies[vert]
        if f_v.size >= 3 and code.cutoff_frequency(f_v[0], f_v[2]) <= limit:
            break
        if limit >= MODE_LIMIT_CAP_HZ:
            if not f_v.size:
                raise err("bridge", label, OUT_OF_RANGE, f"no vertical bending mode below {MODE_LIMIT_CAP_HZ:g} Hz "
                          f"(lowest: {mb.mode_types[0]}, {mb.frequencies[0]:.4g} Hz)")
            break
        limit *= 2.0
    cutoff = code.cutoff_frequency(f_v[0], f_v[2] if f_v.size >= 3 else None)
    f1 = float(f_v[0])
    f3 = float(f_v[2]) if f_v.size >= 3 else None
    used = np.flatnonzero(mb.frequencies <= cutoff * (1.0 + 1e-9))
    terms = {"30 Hz": code.MIN_CUTOFF_HZ, f"1.5 f1 = {1.5 * f1:.3g} Hz": 1.5 * f1}
    if f3 is not None:
        terms[f"f3 = {f3:.3g} Hz"] = f3
    basis = "max(" + ", ".join(terms) + "), f1 and f3 of the vertical bending modes"
    return mb, used, f1, f3, cutoff, basis


__all__ = ["FIRST_MODE_LIMIT_HZ", "MODE_LIMIT_CAP_HZ", "OUT_OF_RANGE", "modes_for_check", "vertical"]
