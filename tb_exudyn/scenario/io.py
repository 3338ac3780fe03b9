"""Loading and saving scenarios, vehicles and bridges as TOML.

``load_scenario`` accepts a path or a name from the model library; names of vehicles and bridges
inside a scenario are resolved the same way (or as paths relative to the scenario file; in a
setting, ``with_settings`` / ``--set``, relative to the working folder).
``save_scenario`` writes the fully resolved scenario (vehicles and bridge inline), so that
loading it again gives an equal object.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Sequence

from ..errors import ArgumentTypeError, OutputFolderError, SettingError
from . import model as m
from .errors import ScenarioError
from .registry import model_path
from .schema import Context, convert, set_source_file, to_dict
from .toml_io import dumps_toml, read_toml, write_text_atomic


def _family(choices: tuple) -> str:
    return "vehicles" if set(choices) <= set(m.VEHICLE_KINDS.values()) else "bridges"


def _resolver(choices: tuple, name: str, ctx: Context) -> Any:
    """Resolve a vehicle or bridge given by name (library) or by a path ending in .toml."""
    family = _family(choices)
    if name.endswith(".toml"):
        base = Path(ctx.file).parent if ctx.file and not ctx.file.startswith("<") else Path.cwd()
        path = (base / name).resolve()
    else:
        path = model_path(family, name, ctx.file, ctx.path)
    return _load_union(choices, path)


def _load_union(choices: tuple, path: Path) -> Any:
    data = read_toml(path)
    ctx = Context(str(path), "", _resolver)
    union = m.Vehicle if _family(choices) == "vehicles" else m.Bridge
    return set_source_file(convert(union, data, ctx), str(path))  # errors found later name this file


def resolve_model_path(path_or_name: str | Path, category: str) -> Path:
    path = Path(path_or_name)
    if path.suffix == ".toml" or path.exists():
        return path
    return model_path(category, str(path_or_name), None, category)


def scenario_from_dict(data: dict, file: str | None = None, resolve_names: bool = True) -> m.Scenario:
    """Build and validate a Scenario from a plain dict (the TOML table); ``file`` names where it was
    read from, in error messages now and later (``Scenario.source_file``, ``Scenario.where``).
    With ``resolve_names=False`` vehicles and bridges must be given inline (no model names or
    paths are looked up: for scenarios stored in result files)."""
    ctx = Context(file, "", _resolver if resolve_names else None)
    return set_source_file(convert(m.Scenario, data, ctx), file)


def parse_setting(text: str) -> tuple[str, Any]:
    """``KEY=VALUE`` of a setting (``--set track.lead_in=150``): the dotted key and the value read as
    a TOML value (150, 1.5e3, true, "text", [1, 2], inf), a bare word that is no TOML value as a
    string (``analysis.freq_spacing=adaptive``). ValueError names what is wrong."""
    key, sep, raw = text.partition("=")
    key, raw = key.strip(), raw.strip()
    if not sep or not key or not raw:
        raise ValueError("KEY=VALUE with a dotted scenario key, e.g. track.lead_in=150")
    import tomllib

    try:
        return key, tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        return key, raw


#: how a setting's value names a file (a vehicle or bridge .toml, a modal table's .csv): resolved from
#: the working folder, as a shell user expects, not from the scenario's folder
FILE_SUFFIXES = (".toml", ".csv")


def from_working_folder(value: Any) -> Any:
    """A setting's value with each relative file name (a string ending in :data:`FILE_SUFFIXES`, also
    inside a list) made absolute from the working folder; names of models and other values as given."""
    if isinstance(value, list):
        return [from_working_folder(v) for v in value]
    if isinstance(value, str) and value.lower().endswith(FILE_SUFFIXES) and not os.path.isabs(value):
        return os.path.abspath(value)
    return value


def with_settings(scenario: m.Scenario, settings: Sequence[tuple[str, Any]]) -> m.Scenario:
    """The scenario with ``settings`` ((dotted key, value), ...: ``("track.lead_in", 150.0)``; a list
    index as a segment: ``train.vehicles.0.body.mass``) applied to its plain form and read again
    through the schema, so that every value is checked as in a file. A file named in a value
    (``("bridge", "my/x.toml")``) is found from the working folder (:func:`from_working_folder`), not
    from the scenario's. Raises ScenarioError naming the key (an unknown key: what the table holds; a
    missing file: the path tried)."""
    data = to_dict(scenario)
    for key, value in settings:
        value = from_working_folder(value)
        node: Any = data
        parts = key.split(".")
        for depth, part in enumerate(parts):
            last = depth == len(parts) - 1
            where = ".".join(parts[:depth + 1])
            if isinstance(node, list):
                if not part.isdigit() or int(part) >= len(node):
                    raise ScenarioError(None, where, part, f"an index 0 ... {len(node) - 1}", "no such entry")
                if last:
                    node[int(part)] = value
                else:
                    node = node[int(part)]
                continue
            if not isinstance(node, dict) or part not in node and not _is_field(node, part):
                known = sorted(node) if isinstance(node, dict) else []
                raise ScenarioError(None, where, value if last else part,
                                    "a key of the scenario: " + (", ".join(known) or "none here"), "unknown key")
            if last:
                node[part] = value
            else:
                node = node.setdefault(part, {})
    return scenario_from_dict(data, scenario.source_file)


def _is_field(table: dict, key: str) -> bool:
    """Whether ``key`` is a key the table may hold although its plain form leaves it out (an absent
    optional table): judged by the schema when the table is read again."""
    return key in ("yaw_damper", "code")


def load_scenario(path_or_name: str | Path) -> m.Scenario:
    """Load a scenario from a TOML file or by name (``tb-exudyn list`` shows the names). Its
    ``[uncertain]`` table, if any, is left to :func:`tb_exudyn.scenario.uncertain.load_study`.

    Raises ScenarioError naming the file, key, value and what is allowed for any bad input.
    """
    path = resolve_model_path(path_or_name, "scenarios")
    data = read_toml(path)
    data.pop("uncertain", None)  # the uncertain keys of `tb-exudyn uq` (scenario/uncertain.py: load_study)
    return scenario_from_dict(data, str(path))


def load_vehicle(path_or_name: str | Path) -> m.Vehicle:
    """Load one vehicle (moving_force, sprung_mass or car15) by path or library name."""
    return _load_union(tuple(m.VEHICLE_KINDS.values()), resolve_model_path(path_or_name, "vehicles"))


def load_bridge(path_or_name: str | Path) -> m.Bridge:
    """Load one bridge (simple_beam or frame) by path or library name."""
    return _load_union(tuple(m.BRIDGE_KINDS.values()), resolve_model_path(path_or_name, "bridges"))


def scenario_to_toml(scenario: m.Scenario) -> str:
    """The TOML text of a resolved scenario (vehicles and bridge written inline)."""
    data = to_dict(scenario)
    header = f"tb_exudyn scenario '{scenario.name}' (resolved: vehicles and bridge inline)"
    return dumps_toml(data, header)


def save_scenario(scenario: m.Scenario, path: str | Path) -> Path:
    """Write the scenario as TOML (atomically); ``load_scenario`` on it gives an equal scenario.

    ``path`` is a file's: a folder or another non-regular entry there is refused (SettingError), and a
    file that cannot be written (a parent that is a file, no permission) is an OutputFolderError naming
    it; either way nothing is left behind."""
    scenario = as_scenario(scenario, "save_scenario")
    if not isinstance(path, (str, os.PathLike)):
        raise ArgumentTypeError("save_scenario", "path", path, "a file path (str or pathlib.Path), e.g. 'mine.toml'",
                                f"a path is a str or a Path, not a value of type {type(path).__name__}")
    path = Path(path)
    if path.is_dir() or (path.exists() and not path.is_file()):
        raise SettingError("save_scenario", "path", str(path), "a file path, e.g. "
                           f"{str(path / (scenario.name + '.toml'))!r}",
                           "is a folder" if path.is_dir() else "exists and is no regular file")
    try:
        write_text_atomic(path, scenario_to_toml(scenario))
    except OSError as exc:
        raise OutputFolderError.from_parts("save_scenario", "path", str(path), "a file in a folder this user can write",
                                           f"cannot be written: {exc.strerror or exc}") from None
    return path


def as_scenario(scenario: Any, where: str) -> m.Scenario:
    """The Scenario a public entry point (``run_pem``, ``simulate``, ...) was given: a Scenario as it is,
    a name or path (str or Path) loaded by :func:`load_scenario`; anything else is an
    ArgumentTypeError (a TypeError) naming ``where`` and what to pass."""
    if isinstance(scenario, m.Scenario):
        return scenario
    if isinstance(scenario, (str, os.PathLike)):
        return load_scenario(scenario)
    raise ArgumentTypeError(where, "scenario", scenario, "a Scenario (tb_exudyn.load_scenario('quick')) or a "
                            "scenario's name or TOML file", f"a value of type {type(scenario).__name__}")
