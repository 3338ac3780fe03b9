"""The methods package (it builds Exudyn models and compiles the integrators), imported only when a
command runs one; the report package is imported likewise by ``results.report_package``."""

from __future__ import annotations


def methods():  # noqa: ANN201
    """The methods (they build Exudyn models): imported when a command runs one."""
    from .. import methods as package

    return package


__all__ = ["methods"]
