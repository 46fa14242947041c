"""Layer a YAML file over dataclass defaults, refusing unknown keys and wrong types.

Every tool keeps its defaults in a dataclass; a YAML file only overrides them. Errors name the
file and the dotted key so that a user can fix the file without reading code.
"""
import dataclasses
import math
import typing

import yaml


class ConfigError(ValueError):
    """A configuration file or value that cannot be used; the message names file and key. A
    tool exits 2 with it (run_main), as for a bad option."""
    status = 2


def bounded(default=dataclasses.MISSING, *, factory=dataclasses.MISSING, above=None,
            at_least=None, at_most=None, finite=False, keys=None):
    """A dataclass field whose loaded value must be > `above`, >= `at_least`, <= `at_most`,
    not infinite with `finite`, and (a mapping) have only `keys`: a value outside is a
    ConfigError naming the file, the key, the value and the allowed range, instead of a stage
    that fails later or silently does nothing. NaN is always refused."""
    limits = {"above": above, "at_least": at_least, "at_most": at_most, "finite": finite,
              "keys": keys}
    return dataclasses.field(default=default, default_factory=factory,
                             metadata={"limits": limits})


def check_fields(config, where=""):
    """Check every bounded field of dataclass `config` as a file's values are checked when
    loaded: for values that came another way (options, node parameters). Returns `config`;
    the ConfigError names the field after `where`."""
    for field in dataclasses.fields(config):
        limits = field.metadata.get("limits")
        if limits:
            _check_limits(getattr(config, field.name), limits, f"{where}{field.name}")
    return config


def _check_limits(value, limits, where):
    if limits["keys"] is not None:
        unknown = sorted(set(value) - set(limits["keys"]))
        if unknown:
            raise ConfigError(f"{where}: unknown key(s) {', '.join(map(str, unknown))} "
                              f"(known: {', '.join(limits['keys'])})")
        return
    allowed = []
    if limits["above"] is not None:
        allowed.append(f"> {limits['above']}")
    if limits["at_least"] is not None:
        allowed.append(f">= {limits['at_least']}")
    if limits["at_most"] is not None:
        allowed.append(f"<= {limits['at_most']}")
    if limits["finite"]:
        allowed.append("finite")
    values = value if isinstance(value, (list, tuple)) else [value]
    for item in values:
        if (limits["above"] is not None and not item > limits["above"]) or \
                (limits["at_least"] is not None and not item >= limits["at_least"]) or \
                (limits["at_most"] is not None and not item <= limits["at_most"]) or \
                (limits["finite"] and not math.isfinite(item)) or \
                (isinstance(item, float) and item != item):
            raise ConfigError(f"{where}: {value!r} is out of range (allowed: "
                              f"{' and '.join(allowed)})")


def _coerce(value, expected_type, where):
    origin = typing.get_origin(expected_type)
    if dataclasses.is_dataclass(expected_type):
        if not isinstance(value, dict):
            raise ConfigError(f"{where}: expected a mapping, got {type(value).__name__}")
        return overlay(expected_type(), value, where)
    if origin is dict:
        key_type, value_type = typing.get_args(expected_type)
        if not isinstance(value, dict):
            raise ConfigError(f"{where}: expected a mapping, got {type(value).__name__}")
        return {_coerce(k, key_type, f"{where}.{k}"): _coerce(v, value_type, f"{where}.{k}")
                for k, v in value.items()}
    if origin in (list, tuple):
        (item_type, *_) = typing.get_args(expected_type)
        if not isinstance(value, list):
            raise ConfigError(f"{where}: expected a list, got {type(value).__name__}")
        return origin(_coerce(v, item_type, f"{where}[{i}]") for i, v in enumerate(value))
    if expected_type is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"{where}: expected a number, got {value!r}")
        return float(value)
    if expected_type is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{where}: expected an integer, got {value!r}")
        return value
    if expected_type is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{where}: expected true or false, got {value!r}")
        return value
    if expected_type is str:
        if not isinstance(value, str):
            raise ConfigError(f"{where}: expected a string, got {value!r}")
        return value
    raise ConfigError(f"{where}: unsupported type {expected_type}")


def overlay(defaults, values, where):
    """Return a copy of dataclass `defaults` with `values` (a dict) laid over it."""
    hints = typing.get_type_hints(type(defaults))
    fields = {field.name: field for field in dataclasses.fields(defaults)}
    changes = {}
    for key, value in values.items():
        if key not in hints:
            known = ", ".join(sorted(hints))
            raise ConfigError(f"{where}: unknown key '{key}' (known keys: {known})")
        changes[key] = _coerce(value, hints[key], f"{where}.{key}")
        limits = fields[key].metadata.get("limits")
        if limits:
            _check_limits(changes[key], limits, f"{where}.{key}")
    return dataclasses.replace(defaults, **changes)


def load_yaml_over(defaults, path):
    """Load `path` (YAML) over dataclass `defaults`; errors name the file and the key."""
    try:
        with open(path, encoding="utf-8") as stream:
            values = yaml.safe_load(stream)
    except OSError as error:
        raise ConfigError(f"{path}: cannot read config: {error.strerror}") from error
    except UnicodeDecodeError as error:
        raise ConfigError(f"{path}: not UTF-8 text (byte {error.start}): not a YAML config") \
            from error
    except (yaml.YAMLError, RecursionError) as error:
        raise ConfigError(f"{path}: not valid YAML: {error}") from error
    if values is None:
        return defaults
    if not isinstance(values, dict):
        raise ConfigError(f"{path}: expected a mapping at the top level")
    return overlay(defaults, values, str(path))
