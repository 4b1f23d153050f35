"""The `dnarod compare` configuration: read a YAML file, check it against
workflows/config/schema.yaml, fill in the defaults.

Errors name the file and the key (as a dotted path, e.g. md.run_ps) and say what is
allowed, with "did you mean" for a misspelt key, like the scene reader does for scenes.
"""
from __future__ import annotations

import copy
import difflib
import math
from pathlib import Path

from dna_models.errors import InputError

SCHEMA_PATH = Path(__file__).resolve().parent / "config" / "schema.yaml"


def schema() -> dict:
    import yaml
    return yaml.safe_load(SCHEMA_PATH.read_text())


def _at(schema_node: dict, path) -> dict:
    for part in path:
        if isinstance(part, int):
            schema_node = schema_node.get("items", {})
        else:
            schema_node = schema_node.get("properties", {}).get(part, {})
    return schema_node


def _key(path) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def _allowed(node: dict) -> str:
    bits = []
    if "enum" in node:
        return "one of " + ", ".join(map(str, node["enum"]))
    t = node.get("type")
    if t:
        bits.append(" or ".join(t) if isinstance(t, list) else t)
    if "minimum" in node:
        bits.append(f">= {node['minimum']}")
    if "exclusiveMinimum" in node:
        bits.append(f"> {node['exclusiveMinimum']}")
    if "minItems" in node:
        bits.append(f"at least {node['minItems']} item(s)")
    return ", ".join(bits)


def _message(err, sch: dict) -> str:
    path = list(err.absolute_path)
    node = _at(sch, path)
    if err.validator == "additionalProperties":
        known = sorted(node.get("properties", {}))
        extra = sorted(set(err.instance) - set(known))
        parts = []
        for k in extra:
            close = difflib.get_close_matches(k, known, n=1)
            hint = f" (did you mean '{_key(path + [close[0]])}'?)" if close else ""
            parts.append(f"unknown key '{_key(path + [k])}'{hint}")
        return "; ".join(parts) + f"; allowed keys{' of ' + _key(path) if path else ''}: {', '.join(known)}"
    if err.validator == "required":
        missing = err.message.split("'")[1]
        desc = node.get("properties", {}).get(missing, {}).get("description", "")
        return f"missing key '{_key(path + [missing])}'" + (f" ({desc})" if desc else "")
    desc = node.get("description", "")
    return (f"key '{_key(path)}' = {err.instance!r}: must be {_allowed(node) or err.message}"
            + (f" ({desc})" if desc else ""))


def _fill_defaults(data: dict, node: dict) -> None:
    for name, sub in node.get("properties", {}).items():
        if name not in data and "default" in sub:
            data[name] = copy.deepcopy(sub["default"])
        if isinstance(data.get(name), dict) and sub.get("type") == "object":
            _fill_defaults(data[name], sub)


def validate(data, source: str = "<config>") -> dict:
    """Check a parsed configuration; return a copy with every default filled in."""
    import jsonschema
    sch = schema()
    if not isinstance(data, dict):
        raise InputError(f"{source}: a configuration is a mapping of keys (see workflows/config/default.yaml), "
                         f"got {type(data).__name__}")
    errors = sorted(jsonschema.Draft7Validator(sch).iter_errors(data), key=lambda e: list(e.absolute_path))
    if errors:
        raise InputError(f"{source}: " + "\n  ".join(_message(e, sch) for e in errors)
                         + "\n  (every key: docs/workflow.md, 'Configuration keys')")
    out = copy.deepcopy(data)
    _fill_defaults(out, sch)
    if float(out["headline_A_v_A_per_ps"]) not in [float(a) for a in out["A_v_A_per_ps"]]:
        raise InputError(f"{source}: key 'headline_A_v_A_per_ps' = {out['headline_A_v_A_per_ps']!r}: must be one "
                         f"of A_v_A_per_ps {out['A_v_A_per_ps']}")
    _check_medium(out, source)
    return out


# build-md's options of the medium, each set by one key of md (md_build_args adds them)
MEDIUM_OPTIONS = {"solvent": "--solvent", "salt_mM": "--salt-mM", "axial_tension_pN": "--axial-tension-pN"}


def _label(a) -> str:
    return f"{float(a):g}"      # the run-folder label of an A_v (workflows/report/report.py fmt_av)


def medium_args(cfg: dict) -> str:
    """build-md's options of md.solvent, md.salt_mM and md.axial_tension_pN; none in vacuum
    (the default), so a vacuum configuration's builds are what they were before these keys."""
    md = cfg["md"]
    if md.get("solvent", "vacuum") == "vacuum":
        return ""
    args = [f"--solvent {md['solvent']}", f"--salt-mM {float(md.get('salt_mM', 0)):g}"]
    if md.get("axial_tension_pN") is not None:
        args.append(f"--axial-tension-pN {float(md['axial_tension_pN']):g}")
    return " ".join(args)


def md_build_args(cfg: dict, A_v) -> str:
    """build-md's extra arguments of the runs at A_v: md.build_args, then md.build_args_per_A_v[A_v]
    (a later option wins), then the medium's (`medium_args`); `{seed}` is left for the caller."""
    md = cfg["md"]
    per = {_label(k): str(v) for k, v in (md.get("build_args_per_A_v") or {}).items()}
    return " ".join(a for a in (md.get("build_args", ""), per.get(_label(A_v), ""), medium_args(cfg)) if a)


def _check_medium(cfg: dict, source: str) -> None:
    """The medium's keys and what goes with them, before anything runs (build-md would refuse the
    same at each build, in its options' names)."""
    md = cfg["md"]
    water = md["solvent"] != "vacuum"
    others = [k for k in schema()["properties"]["md"]["properties"]["solvent"]["enum"] if k != "vacuum"]
    own = {"md.build_args": md.get("build_args", "")}
    own.update({f"md.build_args_per_A_v[{k}]": str(v) for k, v in (md.get("build_args_per_A_v") or {}).items()})
    for key, text in own.items():
        for name, opt in MEDIUM_OPTIONS.items():
            if opt in text.split():
                raise InputError(f"{source}: key '{key}' holds {opt}: set key 'md.{name}' instead (the medium has one "
                                 "place in a configuration)")
        if water and "--axial-pressure" in text.split():
            raise InputError(f"{source}: key '{key}' holds --axial-pressure, the vacuum's zero-tension length; in "
                             "water hold a tension with key 'md.axial_tension_pN' (0 for none)")
    for name in ("salt_mM", "axial_tension_pN"):
        v = md.get(name)
        if v is not None and not math.isfinite(float(v)):
            raise InputError(f"{source}: key 'md.{name}' = {v!r}: must be a finite number")
    if md["salt_mM"] and not water:
        raise InputError(f"{source}: key 'md.salt_mM' = {md['salt_mM']!r}: salt needs water; set key 'md.solvent' to "
                         f"one of {', '.join(others)} (or md.salt_mM to 0)")
    T = md.get("axial_tension_pN")
    if T is None:
        return
    if not water:
        raise InputError(f"{source}: key 'md.axial_tension_pN' = {T!r}: a tension is held by the water's barostat; "
                         f"set key 'md.solvent' to one of {', '.join(others)} (or md.axial_tension_pN to null: a "
                         "fixed box)")
    if md.get("enabled", True):
        bare = [a for a in cfg["A_v_A_per_ps"] if "--thermostat" not in md_build_args(cfg, a).split()]
        if bare:
            raise InputError(f"{source}: key 'md.axial_tension_pN' = {T!r} needs --thermostat in key 'md.build_args' "
                             f"(or md.build_args_per_A_v of A_v = {', '.join(_label(a) for a in bare)}): the "
                             "barostat draws its noise at the thermostat's temperature")
    scales = (cfg.get("dispersion") or {}).get("box_scales") or []
    if scales:
        raise InputError(f"{source}: key 'dispersion.box_scales' = {scales!r}: a stretched box needs a fixed box, and "
                         f"with md.axial_tension_pN = {T!r} the barostat sets the length; run one configuration "
                         "per tension instead (or dispersion.box_scales: [])")


def load(path) -> dict:
    import yaml
    path = Path(path)
    if not path.is_file():
        raise InputError(f"--config {path}: no such file (shipped configs: workflows/config/*.yaml)")
    try:
        data = yaml.safe_load(path.read_text())
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a YAML file (its bytes are binary)") from None
    except yaml.YAMLError as e:
        raise InputError(f"{path}: not valid YAML ({e})") from None
    return validate(data, str(path))
