"""The `dnarod compare` configuration: read a YAML file, check it against
workflows/config/schema.yaml, fill in the defaults.

Errors name the file and the key (as a dotted path, e.g. md.run_ps) and say what is
allowed, with "did you mean" for a misspelt key, like the scene reader does for scenes.
"""
from __future__ import annotations

import copy
import difflib
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
    return out


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
