"""A small typed schema for frozen dataclasses: fields with units, docs and value checks.

Every scenario dataclass declares its fields with :func:`param`; :func:`from_dict` turns a TOML
table into the dataclass and raises :class:`ScenarioError` naming file, key path, value and what
is allowed for unknown keys, missing keys, wrong types and out-of-range values; :func:`to_dict`
is its inverse. No free-form keys: the dataclass is the schema.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import types
import typing
from dataclasses import MISSING, dataclass, field, fields, is_dataclass
from pathlib import Path
from typing import Any, Callable, Literal, get_args, get_origin

from ..errors import one_of
from .errors import ScenarioError


@dataclass(frozen=True)
class Check:
    """A value check: ``low < x`` (or ``<=``), ``x < high`` (or ``<=``), finite unless inf allowed;
    ``zero`` also allows exactly 0 below ``low`` (a part left out); ``why``: the lower bound's reason,
    told in the message of a value below it."""

    low: float | None = None
    high: float | None = None
    low_inclusive: bool = False
    high_inclusive: bool = True
    allow_inf: bool = False
    zero: bool = False
    why: str = ""

    def ok(self, x: float) -> bool:
        if math.isnan(x):
            return False
        if self.zero and x == 0.0:
            return True
        if math.isinf(x) and not (self.allow_inf and x > 0):
            return False
        if self.low is not None and (x < self.low or (x == self.low and not self.low_inclusive)):
            return False
        if self.high is not None and (x > self.high or (x == self.high and not self.high_inclusive)):
            return False
        return True

    def describe(self) -> str:
        parts = []
        if self.low is not None:
            parts.append(f"{'>=' if self.low_inclusive else '>'} {self.low:g}")
        if self.high is not None:
            parts.append(f"{'<=' if self.high_inclusive else '<'} {self.high:g}")
        text = " and ".join(parts) if parts else "any finite number"
        if self.zero:
            text = f"0 or {text}"
        if self.allow_inf:
            text += " (inf allowed: rigid)"
        return text

    def reason(self, x: float) -> str:
        """Why ``x`` is refused: "out of range", and below ``low`` why the lower bound is where it is."""
        below = self.low is not None and not math.isnan(x) and x < self.low
        return f"out of range: {self.why}" if self.why and below else "out of range"


POSITIVE = Check(low=0.0)
NONNEGATIVE = Check(low=0.0, low_inclusive=True)
STIFFNESS = Check(low=0.0, low_inclusive=True, allow_inf=True)
ANY = Check()
RATIO = Check(low=0.0, high=1.0, low_inclusive=True, high_inclusive=False)
#: a train speed [km/h]: above every rail vehicle's record (574.8 km/h wheel on rail, 2007; 603 km/h
#: maglev, 2015), with room for the moving-load theory checks (speed parameter 1 on a 20 m span of
#: 5 Hz: 720 km/h, tests/builder/test_builder_fryba.py); a larger value is a typo or a unit mix-up
SPEED_KMH = Check(low=0.0, high=1000.0)
#: a vehicle's spring per side [N/m]: real suspension springs are 1e5-1e8 N/m (the shipped cars: 3e5 to
#: 8.5e7); 1e10 is five times the linear wheel-rail contact stiffness (analysis.contact_stiffness_z,
#: 2e9), the stiffest element of the model. Beyond it the spring is a rigid link that the time step
#: does not resolve, and in double precision the model loses the motions it locks (1e30 N/m: NaN
#: responses). From below: the softest real spring, an air spring's lateral stiffness, is about 1e5
#: N/m (the shipped: 2e5 upwards); below 1e2 N/m, three orders under it, a 40 t body on four such
#: springs would sway at 0.01 Hz, below every frequency of a crossing: a slip of units (kN/m written
#: as N/m) or a lost exponent. A spring that is not there is 0 where the key allows it, not 1e-300
_VEHICLE_SPRINGS = "railway suspension springs are 1e5 N/m or stiffer; below 1e2 is a slip of units (kN/m)"
_VEHICLE_MASSES = ("rail vehicle parts weigh 1e3 kg or more, with inertias of 1e2 kg m^2 or more; below 1 kg or "
                   "0.1 kg m^2 is a slip of units")
VEHICLE_STIFFNESS = Check(low=1e2, high=1e10, low_inclusive=True, why=_VEHICLE_SPRINGS)
VEHICLE_STIFFNESS_OR_0 = Check(low=1e2, high=1e10, low_inclusive=True, zero=True, why=_VEHICLE_SPRINGS)
#: a vehicle's damper [N s/m]: real railway dampers are 1e3-1e6 N s/m (the shipped cars: 3e4 to 4e5,
#: yaw dampers 3e5); 1e9 is a thousand times the largest. Beyond it the damper is a rigid link and the
#: model loses the motions it locks in round-off (at 1e15 N s/m the ICE car's bogie yaw mode comes out
#: undamped, at 1e30 the responses are NaN)
VEHICLE_DAMPING = Check(low=0.0, high=1e9, low_inclusive=True)
VEHICLE_DAMPER = Check(low=0.0, high=1e9)
#: a vehicle body's mass [kg] and moments of inertia [kg m^2]: the heaviest rail vehicles (locomotives)
#: weigh about 2e5 kg in all, so 1e6 kg is five times that, and 1e9 kg m^2 more than such a mass
#: spread over 100 m (m L^2 / 12 = 8.3e8); a larger value is a unit slip (grams, tonnes squared), and
#: at 1e30 kg the integration overflows and still ends with a result.
#: From below: the lightest part of a rail vehicle, a wheelset or a light bogie, weighs about 1e3 kg
#: (the shipped cars: 1800 kg to 48 t; a tram's wheelset some 600 kg), and its smallest moment of
#: inertia, a wheelset's about its axle, is about 1e2 kg m^2 (the shipped: 150). A mass below 1 kg or an
#: inertia below 0.1 kg m^2 -- three orders under any of them -- is a slip (tonnes for kg, a lost
#: exponent), and a body that light gives modes far above every frequency the run resolves (a bogie's
#: pitch inertia of 1e-300 kg m^2 was accepted and answered)
VEHICLE_MASS = Check(low=1.0, high=1e6, low_inclusive=True, why=_VEHICLE_MASSES)
VEHICLE_MASS_OR_0 = Check(low=1.0, high=1e6, low_inclusive=True, zero=True, why=_VEHICLE_MASSES)
VEHICLE_INERTIA = Check(low=0.1, high=1e9, low_inclusive=True, why=_VEHICLE_MASSES)
#: a bridge's moduli E and G [N/m^2]: bridge materials are 1e10 N/m^2 or stiffer (timber 1e10, concrete
#: 3e10, steel 2.1e11; the softest shipped, a smeared beam, 2.9e9); below 1e7 -- rubber, three orders
#: under timber -- it is a slip of units (MPa or GPa written as N/m^2)
BRIDGE_MODULUS = Check(low=1e7, low_inclusive=True, why="a bridge's E and G are 1e9 N/m^2 or more; below 1e7 is "
                                                        "a slip of units (MPa, GPa)")
#: a bridge section's area [m^2] and second moments / torsion constant [m^4]: railway girders have
#: 1-20 m^2 and 1-100 m^4 (the shipped: 1 m^2, 1.4 m^4 upwards), a light footbridge's steel beam
#: 1e-2 m^2 and 1e-4 m^4; below 1e-4 m^2 (1 cm^2) and 1e-6 m^4 (a 6 cm square bar) it is a slip of
#: units (cm^2, cm^4 or mm^4 written as m^2, m^4)
BRIDGE_AREA = Check(low=1e-4, low_inclusive=True, why="bridge sections are 1e-2 m^2 or more; below 1e-4 is a slip of "
                                                      "units (cm^2)")
BRIDGE_SECOND_MOMENT = Check(low=1e-6, low_inclusive=True, why="bridge sections have 1e-4 m^4 or more; below 1e-6 is "
                                                              "a slip of units (cm^4, mm^4)")
#: a bridge section's mass per length [kg/m] and its polar moment per length [kg m^2/m]: railway girders
#: carry 1e3-5e4 kg/m (the shipped: 2300 upwards), a light footbridge some 1e2 kg/m and 1e1 kg m^2/m;
#: below 1 kg/m and 1e-2 kg m^2/m it is a slip of units (tonnes for kg) or a lost exponent
BRIDGE_MASS_PER_LENGTH = Check(low=1.0, low_inclusive=True, why="bridges weigh 1e2 kg/m or more; below 1 is a slip "
                                                                "of units (t/m)")
BRIDGE_ROT_MASS = Check(low=1e-2, low_inclusive=True, why="a bridge's polar mass moment is 1e1 kg m^2/m or more; "
                                                          "below 1e-2 is a slip of units")


def param(default: Any = MISSING, *, unit: str = "", doc: str = "", check: Check | None = None):
    """Declare a dataclass field with its unit, a one-line description and a value check."""
    meta = {"unit": unit, "doc": doc, "check": check}
    if isinstance(default, (list, dict, set)):
        raise TypeError("use a tuple for sequence defaults")
    if default is MISSING:
        return field(metadata=meta)
    return field(default=default, metadata=meta)


#: the fields that close a data file's table (a vehicle, a bridge): what it is, where it comes from, remarks
DESCRIBED_FIELDS = (("description", "one line for listings"), ("source", "citation of the data"),
                    ("notes", "remarks, values marked [check]"))


def appended_fields(*specs: tuple[str, str, Callable[[], Any]]) -> Callable[[type], type]:
    """A class decorator that gives a data class the fields ``(name, annotation, make the field)`` after
    its own; apply it under ``@dataclass`` (it must run first)."""
    def decorate(cls: type) -> type:
        annotations = cls.__dict__.get("__annotations__", {})
        for name, annotation, make in specs:
            annotations[name] = annotation
            setattr(cls, name, make())
        cls.__annotations__ = annotations
        return cls
    return decorate


#: :data:`DESCRIBED_FIELDS` (str, default "") after a data class's own fields, the same three in every
#: file of models/
described = appended_fields(*((name, "str", lambda doc=doc: param("", doc=doc)) for name, doc in DESCRIBED_FIELDS))


def unit_of(cls: type, name: str) -> str:
    """The unit declared for field ``name`` of dataclass ``cls``."""
    return {f.name: f.metadata.get("unit", "") for f in fields(cls)}[name]


# --------------------------------------------------------------------------------------------
# dict -> dataclass


@dataclass(frozen=True)
class Context:
    """Where a value came from: the file and the dotted key path."""

    file: str | None
    path: str = ""
    #: resolves a string that names a model (a vehicle or bridge file): (choices, name, ctx) -> object
    resolver: Callable[[tuple, str, "Context"], Any] | None = None

    def child(self, key: str | int) -> "Context":
        if isinstance(key, int):
            return Context(self.file, f"{self.path}[{key}]", self.resolver)
        return Context(self.file, f"{self.path}.{key}" if self.path else key, self.resolver)

    def error(self, value: Any, allowed: str, reason: str = "") -> ScenarioError:
        return ScenarioError(self.file, self.path, value, allowed, reason)


def type_name(tp: Any) -> str:
    origin = get_origin(tp)
    if origin is Literal:
        return "one of " + ", ".join(repr(a) for a in get_args(tp))
    if origin is tuple:
        return f"a list of {type_name(get_args(tp)[0])}"
    if origin in (typing.Union, types.UnionType):
        args = [a for a in get_args(tp) if a is not type(None)]
        optional = " (optional)" if len(args) < len(get_args(tp)) else ""
        return " or ".join(type_name(a) for a in args) + optional
    if is_dataclass(tp):
        return f"a table ({tp.__name__})"
    return {float: "a number", int: "an integer", str: "a string", bool: "true or false"}.get(
        tp, getattr(tp, "__name__", str(tp))
    )


def convert(tp: Any, value: Any, ctx: Context, check: Check | None = None) -> Any:
    """Convert a TOML value to type ``tp``, raising ScenarioError on mismatch."""
    origin = get_origin(tp)
    if origin in (typing.Union, types.UnionType) and type(None) in get_args(tp):
        # an optional table: absent in TOML (the default None), or given
        rest = tuple(a for a in get_args(tp) if a is not type(None))
        if value is None:
            return None
        return convert(rest[0] if len(rest) == 1 else typing.Union[rest], value, ctx, check)
    if origin in (typing.Union, types.UnionType):
        return _convert_kind_union(get_args(tp), value, ctx)
    if origin is Literal:
        allowed = get_args(tp)
        if not any(isinstance(value, type(a)) and value == a for a in allowed):  # no array == str
            raise ctx.error(value, ", ".join(repr(a) for a in allowed), "unknown value")
        return value
    if origin is tuple:
        (item_tp, _ellipsis) = get_args(tp)
        if not isinstance(value, (list, tuple)):
            raise ctx.error(value, type_name(tp), "wrong type")
        return tuple(convert(item_tp, v, ctx.child(i), check) for i, v in enumerate(value))
    if is_dataclass(tp):
        if isinstance(value, tp):
            return value
        if not isinstance(value, dict):
            raise ctx.error(value, type_name(tp), "wrong type")
        return from_dict(tp, value, ctx)
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ctx.error(value, "a number" + (f" {check.describe()}" if check else ""), "wrong type")
        value = float(value)
        if check is not None and not check.ok(value):
            raise ctx.error(value, check.describe(), check.reason(float(value)))
        return value
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            if isinstance(value, float) and value.is_integer():
                value = int(value)
            else:
                raise ctx.error(value, "an integer" + (f" {check.describe()}" if check else ""), "wrong type")
        if check is not None and not (abs(value) < 2.0**1000 and check.ok(float(value))):  # float() overflows beyond
            raise ctx.error(value, check.describe(), check.reason(float(value) if abs(value) < 2.0**1000 else
                                                                  math.inf if value > 0 else -math.inf))
        return value
    if tp is str:
        if not isinstance(value, str):
            raise ctx.error(value, "a string", "wrong type")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise ctx.error(value, "true or false", "wrong type")
        return value
    raise TypeError(f"schema type {tp!r} not supported")  # programming error, not user error


def _convert_kind_union(choices: tuple, value: Any, ctx: Context) -> Any:
    """A union of dataclasses told apart by their ``kind``: an object, a table with ``kind``, or a
    string naming a model file (resolved by ``ctx.resolver``)."""
    kinds = {c.kind: c for c in choices}
    allowed = "a model name or a table with kind = " + " | ".join(repr(k) for k in kinds)
    if isinstance(value, choices):
        return value
    if isinstance(value, str):
        if ctx.resolver is None:
            raise ctx.error(value, "kind = " + " | ".join(kinds), "no names here")
        return ctx.resolver(choices, value, ctx)
    if not isinstance(value, dict):
        raise ctx.error(value, allowed, "wrong type")
    if "kind" not in value:
        raise ScenarioError(ctx.file, ctx.child("kind").path, "<missing>", " | ".join(map(repr, kinds)), "missing key")
    kind = value["kind"]
    if kind not in kinds:
        raise ctx.child("kind").error(kind, " | ".join(repr(k) for k in kinds), "unknown kind")
    return from_dict(kinds[kind], {k: v for k, v in value.items() if k != "kind"}, ctx)


def from_dict(cls: type, data: dict, ctx: Context) -> Any:
    """Build dataclass ``cls`` from a TOML table, checking keys, types and values."""
    if not isinstance(data, dict):
        raise ctx.error(data, type_name(cls), "wrong type")
    hints = typing.get_type_hints(cls)
    known = {f.name: f for f in fields(cls) if f.init}
    unknown = sorted(set(data) - set(known))
    if unknown:
        raise ctx.child(unknown[0]).error(
            data[unknown[0]], one_of(known, unknown[0], tail=f" (keys of {cls.__name__})"), "unknown key"
        )
    kwargs = {}
    for name, f in known.items():
        sub = ctx.child(name)
        if name not in data:
            if f.default is MISSING and f.default_factory is MISSING:  # type: ignore[misc]
                raise ScenarioError(ctx.file, sub.path, "<missing>", type_name(hints[name]), "missing key")
            continue
        kwargs[name] = convert(hints[name], data[name], sub, f.metadata.get("check"))
    for name in getattr(cls, "file_keys", ()):  # file names relative to the file read: made absolute
        if kwargs.get(name) and ctx.file and not ctx.file.startswith("<"):
            kwargs[name] = str((Path(ctx.file).parent / kwargs[name]).resolve())
    try:
        return cls(**kwargs)  # Validated.__post_init__ checks values and cross-field rules
    except ScenarioError as exc:  # add the file and the key path of this table
        key = exc.key if exc.key != "<top level>" else ""
        path = f"{ctx.path}.{key}" if ctx.path and key else (ctx.path or key)
        raise ScenarioError(ctx.file if exc.file == "<scenario>" else exc.file, path, exc.value, exc.allowed,
                            exc.reason) from None


# --------------------------------------------------------------------------------------------
# dataclass -> dict


def to_dict(obj: Any) -> Any:
    """The plain (TOML-ready) form of a schema dataclass; ``kind`` class attributes are kept."""
    if is_dataclass(obj):
        out: dict[str, Any] = {}
        kind = getattr(type(obj), "kind", None)
        if isinstance(kind, str) and not any(f.name == "kind" for f in fields(obj)):
            out["kind"] = kind
        for f in fields(obj):
            value = getattr(obj, f.name)
            if value is not None:  # an absent optional table (TOML has no null)
                out[f.name] = to_dict(value)
        return out
    if isinstance(obj, tuple):
        return [to_dict(v) for v in obj]
    return obj


def describe_fields(cls: type) -> list[tuple[str, str, str, str]]:
    """Rows (name, type, unit, doc) for documentation and ``tb-exudyn show``."""
    hints = typing.get_type_hints(cls)
    return [
        (f.name, type_name(hints[f.name]), f.metadata.get("unit", ""), f.metadata.get("doc", ""))
        for f in fields(cls)
    ]


def replace(obj: Any, **changes: Any) -> Any:
    """A modified copy, checked as the TOML loader checks (:func:`convert`) and validated again on
    construction (``dataclasses.replace``); the file the object was read from
    (:func:`set_source_file`) is kept.

    Each changed value is checked against its field's type and value check, so a bool is not a
    number, a string is not a number, NaN, complex numbers and arrays are refused, an integer field
    refuses 8.5 (8.0 is taken as 8, as in TOML), a list becomes a tuple and a numpy scalar a Python
    number. A field holding a dataclass (``analysis``, ``bridge``, a vehicle) takes only an object
    of that dataclass, not a dict: a dict would have to be converted into a whole new object, which
    silently resets every key it does not name to its default; change a nested object with its own
    ``replace`` (``sc.replace(analysis=sc.analysis.replace(n_freq=400))``). Errors are
    ScenarioError ``TYPE.replace: key 'KEY' = VALUE: ...`` naming the key.
    """
    where = f"{type(obj).__name__}.replace"
    hints = typing.get_type_hints(type(obj))
    known = {f.name: f for f in fields(obj) if f.init}
    checked = {}
    for name, value in changes.items():
        if name not in known:
            raise ScenarioError(where, name, value, one_of(known, name, tail=f" (keys of {type(obj).__name__})"),
                                "unknown key")
        checked[name] = _replacement(hints[name], value, Context(where, name), known[name].metadata.get("check"))
    try:
        new = dataclasses.replace(obj, **checked)
    except ScenarioError as exc:  # a cross-field rule of the new object: name where it was changed
        if exc.file != "<scenario>":
            raise
        raise ScenarioError(where, exc.key, exc.value, exc.allowed, exc.reason) from None
    if SOURCE_FILE in obj.__dict__:
        object.__setattr__(new, SOURCE_FILE, obj.__dict__[SOURCE_FILE])
    return new


def _plain(value: Any) -> Any:
    """A numpy scalar as the Python number it holds (an int as int, a real as float); anything else
    as it is (a numpy bool or complex stays refused by :func:`convert`)."""
    if isinstance(value, (bool, int, float, str)) or not isinstance(value, numbers.Real):
        return value
    return int(value) if isinstance(value, numbers.Integral) else float(value)


def _replacement(tp: Any, value: Any, ctx: Context, check: Check | None) -> Any:
    """A value given to ``replace`` checked against the field type ``tp``: as :func:`convert`, except
    that a dataclass field takes an object of its class only (no dict, no model name)."""
    origin = get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        args = get_args(tp)
        rest = tuple(a for a in args if a is not type(None))
        if value is None and len(rest) < len(args):
            return None
        if all(is_dataclass(a) for a in rest):
            if isinstance(value, rest):
                return value
            raise ctx.error(value, " or ".join(f"an object of class {a.__name__}" for a in rest)
                            + (" or None" if len(rest) < len(args) else ""), _dataclass_reason(value))
        return _replacement(rest[0] if len(rest) == 1 else typing.Union[rest], value, ctx, check)
    if is_dataclass(tp):
        if isinstance(value, tp):
            return value
        raise ctx.error(value, f"an object of class {tp.__name__}", _dataclass_reason(value))
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise ctx.error(value, type_name(tp), "wrong type")
        (item_tp, _ellipsis) = get_args(tp)
        return tuple(_replacement(item_tp, v, ctx.child(i), check) for i, v in enumerate(value))
    return convert(tp, _plain(value), ctx, check)


def _dataclass_reason(value: Any) -> str:
    if isinstance(value, dict):
        return "a dict is not taken (it would reset the keys it does not name): use the object's replace()"
    return "wrong type"


#: attribute (not a dataclass field: not compared, not saved) holding the file an object was read from
SOURCE_FILE = "_source_file"


def set_source_file(obj: Any, file: str | None) -> Any:
    """Remember on a (frozen) schema object the file it was read from; returns ``obj``."""
    if file is not None:
        object.__setattr__(obj, SOURCE_FILE, str(file))
    return obj


def source_file(obj: Any) -> str | None:
    """The file a schema object was read from (:func:`set_source_file`), or None."""
    return obj.__dict__.get(SOURCE_FILE)


class Validated:
    """Mixin for schema dataclasses: every construction (from TOML, in Python, by ``replace``)
    checks each field's value check and then the class's own cross-field ``_validate``."""

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            check = f.metadata.get("check")
            if check is None:
                continue
            value = getattr(self, f.name)
            items = value if isinstance(value, tuple) else (value,)
            for i, item in enumerate(items):
                if isinstance(item, (int, float)) and not isinstance(item, bool) and not check.ok(float(item)):
                    key = f"{f.name}[{i}]" if isinstance(value, tuple) else f.name
                    raise ScenarioError(None, key, item, check.describe(), check.reason(float(item)))
        validate = getattr(self, "_validate", None)
        if validate is not None:
            validate(Context(None))
