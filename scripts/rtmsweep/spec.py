"""A sweep spec (docs/sweeps.md, "The spec"): parsed and checked once, then expanded into jobs.

A job is one configuration as a dict: the rtm render arguments (scene, size, pes, partition,
search_units, timing, precision, preset, config, set), its run id, and what sweep-run needs to make
its row (set_keys, variant, images, timeout). scripts/sweep hands each job to sweep-run as JSON.
"""

import dataclasses
import hashlib
import itertools
import json
import math
import os
import re

import yaml

from . import checkout

# Top-level spec axes, each an rtm render option (run.AXIS_OPTIONS).
AXES = ["pes", "partition", "search_units", "timing", "precision"]
SPEC_KEYS = {"name", "description", "scene_dir", "scenes", "sizes", "set", "variants", "preset", "config",
             "timeout", "images"} | set(AXES)
NAME_PATTERN = r"[A-Za-z0-9._-]+"


class SpecError(Exception):
    """A spec that cannot be run: the message says which key and why."""


@dataclasses.dataclass
class Variant:
    """A named machine: fixed `set` values and its own values of top-level axes, on top of its
    own preset (None: the spec's)."""
    name: str
    settings: dict
    axes: dict
    preset: str = None


@dataclasses.dataclass
class Spec:
    name: str
    scenes: list            # absolute paths
    sizes: list             # "WxH", or [None]: each scene's own size
    axes: dict              # AXES -> list of values ([None]: not passed to rtm)
    set_values: dict        # `set` key -> list of values as rtm reads them, in spec order
    variants: list          # of Variant; empty when the spec has none
    preset: str = None      # --preset of every run whose variant names none
    config: str = None      # --config file for every run
    timeout: float = None   # seconds per run
    images: bool = True     # keep each run's PNG

    @property
    def presets(self):
        """The presets the spec names, in order (top level first)."""
        named = [self.preset] + [v.preset for v in self.variants]
        return list(dict.fromkeys(p for p in named if p is not None))

    @property
    def set_keys(self):
        """The spec's own CSV columns, in order: `variant` (if any), `preset` (if the spec names
        one), then the `set` keys."""
        return (["variant"] if self.variants else []) + (["preset"] if self.presets else []) + list(self.set_values)

    def jobs(self):
        """The cartesian product, one job per distinct configuration; the PE count varies
        fastest, so each configuration's series is contiguous."""
        set_keys = list(self.set_values)
        jobs, seen = [], set()
        for scene, size, variant, partition, search_units, timing, precision, *rest in itertools.product(
                self.scenes, self.sizes, self.variants or [Variant(None, {}, {})], self.axes["partition"],
                self.axes["search_units"], self.axes["timing"], self.axes["precision"],
                *[self.set_values[k] for k in set_keys], self.axes["pes"]):
            set_combo, pes = rest[:-1], rest[-1]
            identity = {"scene": scene, "size": size, "pes": pes, "partition": partition,
                        "search_units": search_units, "timing": timing, "precision": precision,
                        "set": {**variant.settings, **dict(zip(set_keys, set_combo))}, "config": self.config}
            identity.update(variant.axes)
            if variant.name is not None:
                identity["variant"] = variant.name
            # Only when named, so that the ids of specs without presets stay what they were.
            preset = variant.preset or self.preset
            if preset is not None:
                identity["preset"] = preset
            rid = run_id(identity)
            if rid in seen:
                continue  # a value listed twice
            seen.add(rid)
            job = {"id": rid, **{k: v for k, v in identity.items() if v is not None and k != "set"},
                   "set": identity["set"], "set_keys": self.set_keys, "images": self.images}
            if self.timeout is not None:
                job["timeout"] = self.timeout
            jobs.append(job)
        return jobs


def run_id(identity):
    """SCENE[-WxH][-pN]-HASH: HASH is 8 hex digits of a hash over every setting, so the same
    configuration gets the same id whatever the order of the spec's lists (resuming relies on it).
    The scene and config files in the checkout count by their paths in it, so that a copy of the
    checkout elsewhere resumes the same runs."""
    files = {k: checkout.relative(identity[k]) for k in ("scene", "config") if identity.get(k)}
    digest = hashlib.sha1(json.dumps({**identity, **files}, sort_keys=True).encode()).hexdigest()[:8]
    stem = re.sub(r"[^A-Za-z0-9._-]", "_", os.path.splitext(os.path.basename(identity["scene"]))[0])
    size, pes = identity.get("size"), identity.get("pes")
    return "-".join([stem] + ([size] if size else []) + ([f"p{pes}"] if pes else []) + [digest])


def text(value):
    """A spec value as rtm reads it (YAML booleans as true/false)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _as_list(value, key):
    if value is None:
        return [None]
    values = value if isinstance(value, list) else [value]
    if not values:
        raise SpecError(f"{key}: an empty list")
    for v in values:
        if isinstance(v, (dict, list)) or v is None:
            raise SpecError(f"{key}: values must be scalars, got {v!r}")
    return values


def _path(value, base):
    p = os.path.expanduser(os.path.expandvars(str(value)))
    return os.path.normpath(p if os.path.isabs(p) else os.path.join(base, p))


def _is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def _preset(value, where):
    """A preset's name (rtm checks that it knows it), or None."""
    if value is None:
        return None
    if not isinstance(value, str) or not re.fullmatch(NAME_PATTERN, value):
        raise SpecError(f"{where}: {value!r} is not a preset name (rtm render --help lists them)")
    return value


def _sizes(value):
    sizes = []
    for s in _as_list(value, "sizes"):
        if s is None:
            sizes.append(None)
            continue
        m = re.fullmatch(r"(\d+)(?:x(\d+))?", str(s).strip())
        if not m or int(m.group(1)) < 1 or (m.group(2) and int(m.group(2)) < 1):
            raise SpecError(f"sizes: {s!r} is not WxH (e.g. 512x512) or N")
        sizes.append(f"{m.group(1)}x{m.group(2) or m.group(1)}")
    return sizes


def _variants(value, set_values, config_keys):
    if value is None:
        value = {}
    if not isinstance(value, dict) or not all(isinstance(v, dict) or v is None for v in value.values()):
        raise SpecError("variants: expected a mapping NAME: {KEY: value, ...}")
    variants = []
    for name, settings in value.items():
        name = str(name)
        if not re.fullmatch(NAME_PATTERN, name):
            raise SpecError(f"variants: {name!r}: use letters, digits, '.', '_' and '-'")
        fixed, axis_values, preset = {}, {}, None
        for key, v in (settings or {}).items():
            key = str(key)
            if key == "preset":
                preset = _preset(v, f"variants: {name}: preset")
                continue
            if key == "pes" or key in set_values:
                raise SpecError(f"variants: {name}: {key} is also a sweep axis; set it in one place")
            if key in AXES:
                # The variant's own value of a top-level axis (e.g. its partitioning scheme).
                axis_values[key] = v if _is_int(v) else text(v)
                continue
            if config_keys is not None and key not in config_keys:
                raise SpecError(f"variants: {name}: {key}: unknown machine configuration key (rtm config lists them)")
            fixed[key] = text(v)
        variants.append(Variant(name, fixed, axis_values, preset))
    return variants


def parse(data, base, config_keys=None, default_name="sweep"):
    """The Spec of a parsed YAML document. BASE is the folder relative paths start from;
    CONFIG_KEYS the machine-configuration keys `set` and variants may use (None: any)."""
    if not isinstance(data, dict):
        raise SpecError("expected a mapping of keys (name, scenes, sizes, pes, ...)")
    unknown = sorted(map(str, set(data) - SPEC_KEYS))  # YAML keys may be numbers, booleans or null
    if unknown:
        raise SpecError(f"unknown key(s) {', '.join(unknown)}; allowed: {', '.join(sorted(SPEC_KEYS))}")

    name = str(data.get("name") or default_name)
    if not re.fullmatch(NAME_PATTERN, name):
        raise SpecError(f"name {name!r}: use letters, digits, '.', '_' and '-'")
    scene_dir = _path(data["scene_dir"], base) if data.get("scene_dir") is not None else base
    if not data.get("scenes"):
        raise SpecError("scenes: at least one scene file is required")
    scenes = [_path(s, scene_dir) for s in _as_list(data["scenes"], "scenes")]
    sizes = _sizes(data.get("sizes"))

    axes = {}
    for key in AXES:
        values = _as_list(data.get(key), key)
        if key in ("pes", "search_units"):
            for v in values:
                if v is not None and (not _is_int(v) or v < 1):
                    raise SpecError(f"{key}: {v!r} is not a positive integer")
        axes[key] = [v if v is None or isinstance(v, int) else text(v) for v in values]

    sets = data.get("set") or {}
    if not isinstance(sets, dict):
        raise SpecError("set: expected a mapping KEY: [values]")
    set_values = {}
    for key, values in sets.items():
        key = str(key)
        if key in AXES:
            raise SpecError(f"set: {key} is a top-level key of the spec (write {key}: [...])")
        if key == "preset":
            raise SpecError("set: preset is not a key but where the keys start: write preset: NAME at the top "
                            "level or in a variant")
        if config_keys is not None and key not in config_keys:
            raise SpecError(f"set: {key}: unknown machine configuration key (rtm config lists them)")
        set_values[key] = [text(v) for v in _as_list(values, f"set.{key}")]

    variants = _variants(data.get("variants"), set_values, config_keys)

    config = _path(data["config"], base) if data.get("config") else None
    timeout = data.get("timeout")
    if timeout is not None and (isinstance(timeout, bool) or not isinstance(timeout, (int, float))
                                or not math.isfinite(timeout) or timeout <= 0):
        raise SpecError(f"timeout: {timeout!r} is not a positive number of seconds")
    images = data.get("images", True)
    if not isinstance(images, bool):
        raise SpecError(f"images: {images!r} is not true or false")
    return Spec(name=name, scenes=scenes, sizes=sizes, axes=axes, set_values=set_values,
                variants=variants, preset=_preset(data.get("preset"), "preset"), config=config, timeout=timeout,
                images=images)


def load(path, config_keys=None):
    """The Spec in a YAML file; relative paths in it are relative to its folder."""
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise SpecError(f"cannot read {path}: {e.strerror}")
    except yaml.YAMLError as e:
        raise SpecError(f"{path}: not valid YAML: {e}")
    except UnicodeDecodeError as e:
        raise SpecError(f"{path}: not UTF-8 text: {e}")
    if not isinstance(data, dict):
        raise SpecError(f"{path}: expected a mapping of keys (name, scenes, sizes, pes, ...)")
    return parse(data, os.path.dirname(os.path.abspath(path)), config_keys,
                 default_name=os.path.splitext(os.path.basename(path))[0])
