"""Generated spec files, from near-valid specs to any bytes: the spec loader (spec.load, what
scripts/sweep calls) accepts each, with jobs that can be listed, or refuses it with SpecError and a
message, never another exception (docs/reliability.md, "Fuzzing")."""

import math
import string

import yaml
from hypothesis import HealthCheck, event, given, settings, strategies as st

from rtmsweep import spec

KEYS = {"loop_credits", "broadcast", "search_fifo_depth", "gather"}  # the configuration keys `set` may use

# Short runs in the suite, the same examples every time; no example database in the checkout.
suite = settings(max_examples=200, deadline=2000, derandomize=True, database=None,
                 suppress_health_check=[HealthCheck.too_slow])

names = st.text(string.ascii_letters + string.digits + "._-/ *$~", max_size=12)
scalars = (st.none() | st.booleans() | st.integers(-3, 10) | st.integers() | st.floats()
           | names | st.sampled_from(["16x16", "8", "0x4", "paper", "default", "a.nff", "fast", "1e3"]))
# What YAML can hold: scalars, and lists and mappings of them, a few levels deep.
hashable = scalars.filter(lambda k: not isinstance(k, float) or k == k)  # a NaN key is never found again
values = st.recursive(scalars, lambda inner: st.lists(inner, max_size=3) | st.dictionaries(hashable, inner, max_size=3),
                      max_leaves=8)
set_keys = st.sampled_from(sorted(KEYS) + ["preset", "pes", "timing", "warp_drive"]) | names
value = st.one_of(values,
                  st.lists(scalars, min_size=1, max_size=3),
                  st.dictionaries(set_keys, st.lists(scalars, max_size=3) | scalars, max_size=3),  # set
                  st.dictionaries(names, st.dictionaries(set_keys, scalars, max_size=3) | st.none(), max_size=3))
# Each key's value: of the shape it takes (mostly one it accepts), or anything.
shaped = {
    "name": names, "description": names, "scene_dir": names, "config": names,
    "scenes": st.lists(names, min_size=1, max_size=2),
    "sizes": st.lists(st.sampled_from(["16x16", "8", "4x2", "0x3", "x"]) | st.integers(-1, 64), min_size=1, max_size=2),
    "pes": st.lists(st.integers(0, 8), min_size=1, max_size=3) | st.integers(0, 8),
    "search_units": st.integers(0, 4), "partition": st.sampled_from(["scanlines", "blocks", 3]),
    "timing": st.sampled_from(["fast", "clocked"]), "precision": st.sampled_from(["fp32", "fp64"]),
    "set": st.dictionaries(set_keys, st.lists(scalars, max_size=2) | scalars, max_size=2),
    "variants": st.dictionaries(names, st.dictionaries(set_keys | st.sampled_from(["partition", "preset"]), scalars,
                                                       max_size=2) | st.none(), max_size=2),
    "preset": st.sampled_from(["paper", "default", "pa per"]) | scalars,
    "timeout": st.floats() | st.integers(-1, 100), "images": st.booleans() | scalars,
}
# A spec: scenes and any of its own keys, each value of its shape, or (mixed) of any.
shaped_specs = st.fixed_dictionaries({"scenes": shaped["scenes"]},
                                     optional={k: shaped[k] for k in sorted(spec.SPEC_KEYS - {"scenes"})})
mixed_specs = st.builds(lambda own, stranger: {**stranger, **own},
                        st.fixed_dictionaries({"scenes": shaped["scenes"] | value},
                                              optional={k: shaped[k] | value for k in sorted(spec.SPEC_KEYS - {"scenes"})}),
                        st.dictionaries(hashable, value, max_size=1))


def check_loaded(path):
    """The loader's verdict on the file at PATH: a Spec whose jobs can be listed, or SpecError."""
    try:
        s = spec.load(str(path), KEYS)
    except spec.SpecError as e:
        assert str(e), "a SpecError without a message"
        event("refused")
        return
    event("accepted")
    assert s.timeout is None or (math.isfinite(s.timeout) and s.timeout > 0), s.timeout
    for job in s.jobs():
        assert job["id"] and job["scene"], job
        assert set(job["set"]) <= KEYS, job


@suite
@given(shaped_specs | mixed_specs)
def test_a_generated_spec_is_accepted_or_refused_with_a_spec_error(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("spec") / "s.yaml"
    path.write_text(yaml.safe_dump(data))
    check_loaded(path)


@suite
@given(st.text(string.printable + "äé€\u2028", max_size=200) | st.binary(max_size=200))
def test_any_file_is_accepted_or_refused_with_a_spec_error(tmp_path_factory, content):
    path = tmp_path_factory.mktemp("spec") / "s.yaml"
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    check_loaded(path)
